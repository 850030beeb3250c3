// Retargeting: plays a clip (motion/clip.h: a BVH file read by io/bvh/bvh_load.h, or a glTF
// animation read by io/gltf/gltf_clip_load.h) on a model's skeleton, as deform::Poses
// (motion/clip_poses.h).
//
// Joint matching (each BVH joint drives at most one model joint and vice versa), in order:
//   1. name_map   an optional JointNameMap (motion/joint_name_map.h; from a JSON file
//                 {"BVH joint name": "model joint name", ...} through io/json/joint_name_map_json.h);
//                 a pair without a model joint leaves that BVH joint unmapped. Unknown names
//                 are std::invalid_argument naming the map's source.
//   2. name       the same joint name on both sides (exact, case-sensitive).
//   3. role       the same RigMap role (deform::detect_rig_map on both skeletons; see
//                 deform/rig/rig_naming.h): pelvis, chest, head, clavicles, upper/lower limbs,
//                 hands, hip links, feet, toes — so CMU names drive Unreal or Mixamo rigs.
//   4. hierarchy  an unmatched joint that is the only unmatched child of a matched joint on
//                 both sides (e.g. CMU's LFingers under LeftFingerBase ↔ LeftHandFinger1,
//                 when the name map drives the fingers).
// What is left on either side is reported (unmapped_*) and named in warnings (at most 12 names
// each, motion/name_list.h): the clip joints that drive no model joint, and the model joints
// left without motion (unmatched, or matched but not driven: the toes below); unmapped model
// joints keep their rest rotation relative to their parent, unmapped BVH joints still move
// their mapped descendants.
//
// Fingers and thumbs: the clip's joints below its hands (the BVH rig map's hand roles; CMU's
// LeftFingerBase, LFingers, LThumb) are left unmapped unless the name map pairs them, so the
// model's hand moves rigidly with the clip's hand joint. Optical mocap does not measure them:
// CMU puts no marker on a finger or thumb joint, and its solver's fits are noise (RThumb in
// cmu_01_03 swings through ±180° and flips by up to 180° between frames; a smooth 30-60° thumb
// turn in the others stretches the model's skinned thumb webbing 3-4x).
//
// Toes: the clip's toe joints (the BVH rig map's toe roles and anything below them) stay
// matched, so they still aim the model's foot (its A below), but are not driven unless the name
// map pairs them: the model's toes keep their rest rotation relative to the foot. Marker sets
// in the Plug-in-Gait style put the toe marker over a metatarsal head, at the toe joint, so no
// marker moves with the toes, and the solved channels are noise: in cmu_01_03 the toes step by
// more than 10° between consecutive 120 Hz frames in 373 (left) and 154 (right) frames, up to
// 60° in one frame (the feet: 50 and 10), and curl 61° about a hinge tilted 20° from the foot's
// sideways axis, past the 40-45° a toe curls and through the floor, which stretched the skinned
// crease at the ball of the foot 4.1x.
//
// Rotations are retargeted relative to each side's rest pose, in world space. For a model joint
// m driven by BVH joint b:  W_m(frame) = D_b(frame) * A_m * W_m(rest), where
//   D_b  the world rotation BVH joint b undergoes from its rest pose (all channels zero; a glTF
//        clip's rest is its nodes' rest rotations): W_b(frame) * W_b(rest)^-1,
//   A_m  the rotation taking m's rest bone direction (towards its single matched child) onto
//        b's rest bone direction (towards that child's BVH joint); joints with no or several
//        matched children (the root, hands, the chest) take the A of their nearest matched
//        ancestor (the identity at the root). The model's neck chain (its rig map's neck to
//        head) takes the identity: its rest angles are anatomy, not pose.
// So at the BVH's rest T-pose an A-pose model stands in a T-pose, and in every frame each of
// its matched limb and spine bones points where the BVH's bone points; twist about the bone
// follows the BVH. A neck that leans at rest turns with the clip's but keeps its lean, and the
// head turns exactly as the clip's head (aligning the neck's bone to the clip's, as limbs are,
// turned the male's head up to 19.7° away from the clip's head, the mannequin's 15.7°, and a
// neck leaning 25° tilted an upright head by 25°: tests/motion/rest_pose_alignment_test.cpp).
// A clavicle (the rig map's) more than 5° from the clip's at rest keeps its rest angle to the
// chest instead, with the chest's A: skeletons disagree on
// where a clavicle starts, and CMU's, calibrated in a T-pose, rises 20° from the neck's base
// while the male's and the mannequin's fall 10-13° from the sternum; aligned like limbs, the
// model's shoulder joints stood 8.6 cm (male) and 10 cm (mannequin) above their rest height in
// every frame, with every method, and lowered arms read as epaulettes. Where the clip leaves a
// clavicle still (every frame within 2° of its first, as CMU's are: its solver does not move
// them), such a clavicle follows its arm instead (the shoulder rhythm): it turns up or down by a
// third of the arm's elevation above or below the model's rest arm (Inman's 2:1 of arm to
// shoulder girdle), at most 45°, measured from the chest's down axis; the upper arm keeps its
// world rotation, so the arm still points where the clip's points. A clip that moves its
// clavicles drives them as any other joint. Hip links (the rig map's leg.hip) set more than 5°
// from the clip's keep their rest angle to the pelvis in the same way: CMU's LHipJoint falls
// 48° from the pelvis to the hip joint, the male's 2.8°, and aligned, the male's hip joints sat
// 7.6 cm low in every frame (the crotch stretched: LBS's hips 8.3x on cmu_01_01, now 6.1x;
// tests/motion/hip_links_test.cpp).
// The spine is still aligned: keeping the male's lumbar lean (6° and 8° from CMU's) stretched
// a hip edge 3.26x in cmu_01_03 (frame 1128), past the 3x bound. Onto a copy of the clip's own
// skeleton every driven rotation is the clip's.
// Facing: a model built facing another way than the clip (an armature turned 90° in Blender, a
// character modelled facing +X) would walk sideways, its spine and hips keeping their own
// facing. Each side's rest forward is found from its body, not assumed +Z: left is from its
// right arm to its left arm (from the thighs without arms), by the rig map's sides (names, or
// the toes for a topological map), forward is left x up (deform::rest_body_axes). Where the
// two differ by more than kSameFacingDegrees about the vertical, every A_m above is composed
// with the yaw F that turns the model's forward onto the clip's (A_m = arc(F m, b) * F), an
// undriven root turns by F too, and a warning says so: the model then faces where the clip
// faces at every frame, and moves along the clip's own path.
// The local rotations of the Pose are W_parent^-1 * W_m. Joint scale is ignored (rotations only).
//
// Root translation: the model's pelvis goes to root_scale() times the BVH pelvis position,
// where root_scale() = model hip height / BVH hip height. Each side's hip height is its pelvis
// height above the floor when standing on straight legs, whatever the legs' splay at rest: the
// drop from the pelvis to the hip joint, plus thigh and shin lengths (from the rest pose), plus
// the ankles' height above the floor (means of both legs). The model's ankles are measured in
// its rest pose above its lowest vertex (its lowest joint for a bare skeleton); the clip's as
// it stands: the 10th percentile over its frames of the lower ankle's height above y = 0, the
// floor of mocap data (CMU's: 0.100 m on cmu_01_01, 0.086 m on cmu_01_03). A clip's rest
// skeleton need not have a heel: CMU's lowest End Site, its toes', lies 2.4 cm below its ankle,
// and a scale from that put the male's pelvis 7 cm too high. Where that percentile lies at or
// below y = 0 or above a quarter of the clip's straight legs (a clip that sits or hangs, or
// whose floor is elsewhere; a warning says so), the clip's ankles are measured in its rest pose
// above its lowest joint or End Site. Without a rig map on a side, the pelvis height above the
// floor. Both sides must be Y-up (io::load_bvh turns a Z-up clip upright,
// motion/clip_up_axis.h); their length units may differ.
// The shift is applied to the model's root (joint 0), which must carry the pelvis rigidly.
//
// Feet (Feet::kPlanted, the default, on a model with a mesh and a leg the rig map found whole):
// the poses above, then the feet put on the floor where the clip plants them, by leg IK and,
// where a straightened leg cannot reach, by bringing the body down (motion/foot_planting.h).
// Only the legs' hip, knee and ankle rotations and the root's height change; a planted foot's
// ankle moves up or down onto the floor and across so that its sole holds still, about where
// the clip's stands (footfalls keep their places); the feet's world rotations are the clip's.
// Then the whole body rises where another part would go below the floor (knees, hips, hands,
// back: the model's proportions are not the clip's; motion/body_floor.h), with a warning naming
// the largest rise. Parts other than the feet that rest on the floor (the back and hips, knees,
// hands, arms) are held still there while they rest: the root shifted across where the back or
// hips rest, the limbs by IK (motion/body_contacts.h); foot planting and the body floor are then
// built again over those holds. Feet::kPlantedOnly plants and lifts without these holds (to
// measure them). A knee the clip rests on its floor (motion/clip_resting_knees.h) that the
// model's proportions hold above the model's floor brings the body down with it (foot
// planting's drop, the planted legs' IK taking it up) until it lies within a resting part's
// contact height, as far as the body floor lets it (a part already on the floor stops it).
// Feet::kFree
// (and a bare skeleton, which has no soles) keeps every rotation above: onto a copy of the
// clip's own skeleton the clip's rotations come back.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "deform/model/model.h"
#include "deform/model/pose.h"
#include "deform/model/skeleton.h"
#include "deform/rig/rig_map.h"
#include "motion/body_contacts.h"
#include "motion/body_floor.h"
#include "motion/clip.h"
#include "motion/clip_poses.h"
#include "motion/foot_planting.h"
#include "motion/joint_name_map.h"

namespace sweepd::motion {

enum class JointMatchReason { kNameMap, kName, kRole, kHierarchy };
const char* to_string(JointMatchReason reason);

struct JointMatch {
  int bvh_joint = -1;    // index into Clip::joints
  int model_joint = -1;  // index into Skeleton::joints
  JointMatchReason reason = JointMatchReason::kName;
  // false: paired only to aim its parent's bone (a toe, see above); the model joint keeps its
  // rest rotation relative to its parent.
  bool driven = true;
};

// What a model's feet do where the clip plants its feet.
enum class Feet {
  kPlanted,  // put on the floor by leg IK (motion/foot_planting.h)
  kFree,     // where the retargeted rotations and root put them
  // Planted, and the body lifted where a part would go below the floor, but no other part
  // held where it rests on the floor (motion/body_contacts.h): what the body did before those
  // holds, kept to measure them (body_contacts() then finds the contacts, holding nothing).
  kPlantedOnly,
};

class Retargeter final : public ClipPoses {
 public:
  // Throws std::invalid_argument for a name map naming joints the clip or the model lacks (or
  // pairing a joint twice), when the clip has no joints or frames, or the skeleton no joints.
  // The model's floor is its lowest vertex.
  Retargeter(Clip motion, const deform::Model& model, const JointNameMap& name_map = {},
             Feet feet = Feet::kPlanted);
  // A bare skeleton (no soles to plant: Feet::kFree): its floor is its lowest joint.
  Retargeter(Clip motion, deform::Skeleton skeleton, const JointNameMap& name_map = {});
  // A bare skeleton whose mesh's lowest point is known (e.g. from sweepd's ModelInfo): the same
  // retargeting as from the model itself.
  Retargeter(Clip motion, deform::Skeleton skeleton, const JointNameMap& name_map,
             float model_floor);
  // A clip shared with other players (sweepd plays one uploaded clip on many models): the
  // frames are not copied.
  Retargeter(std::shared_ptr<const Clip> motion, const deform::Model& model,
             const JointNameMap& name_map = {}, Feet feet = Feet::kPlanted);

  // Matched pairs, ordered by model joint.
  const std::vector<JointMatch>& matches() const { return matches_; }
  // BVH joint matched to model joint m (driven or not, see JointMatch::driven), or -1.
  int bvh_joint_for(int model_joint) const { return bvh_of_model_[model_joint]; }
  std::vector<std::string> unmapped_bvh_joints() const;
  std::vector<std::string> unmapped_model_joints() const;
  // Problems that did not stop retargeting (e.g. no rig map on one side: no role matching),
  // and the joints left unmapped on either side (see the header).
  const std::vector<std::string>& warnings() const override { return warnings_; }
  // Feet planted on the floor (motion/foot_planting.h), or null: a bare skeleton, or a model
  // without a leg the rig map found whole.
  const FootPlanting* foot_planting() const { return planting_ ? &*planting_ : nullptr; }
  // Parts other than the feet resting on the floor, held there (motion/body_contacts.h), or
  // null where foot_planting() is or no part rests on the floor; with Feet::kPlantedOnly found
  // (never null then, with a foot planting) but not held.
  const BodyContacts* body_contacts() const {
    return body_contacts_ ? &*body_contacts_ : measured_contacts_ ? &*measured_contacts_ : nullptr;
  }

  float root_scale() const { return root_scale_; }
  // L: the model's hip height on straight legs (m), which foot planting and the holds scale by.
  float model_hip_height() const { return model_hip_height_; }
  const Clip& motion() const override { return *motion_; }

  // Sampling is const and thread-safe; each call allocates a few per-joint scratch vectors
  // (tens of joints: microseconds), which is fine per frame but not per vertex.
  // The model posed as frame `frame`. Throws std::out_of_range outside [0, frame_count()).
  deform::Pose pose_at_frame(int frame) const override;
  // The clip's local pose at a time (Clip::local_pose_at_time: between a BVH's frames
  // rotations slerped and translations lerped), then retargeted. seconds is clamped to
  // [0, duration()]; NaN is std::invalid_argument.
  deform::Pose pose_at_time(double seconds) const override;
  // The model posed as the BVH's rest pose (every channel zero); root at its rest translation.
  deform::Pose pose_at_bvh_rest() const;

 private:
  using OptionalRigMap = std::optional<deform::RigMap>;
  void match_joints(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                    const OptionalRigMap& bvh_map, const JointNameMap& name_map);
  // The warnings naming the clip joints mapped to no model joint (but the fingers, which
  // have their own) and the model joints left without motion (unmatched or not driven).
  void warn_unmapped(const deform::Skeleton& bvh, const std::vector<bool>& is_finger);
  // The facing turn (see the header): the yaw taking the model's rest forward onto the clip's.
  void compute_facing(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                      const OptionalRigMap& bvh_map);
  void compute_alignments(const deform::Skeleton& bvh, const OptionalRigMap& model_map);
  void compute_root_scale(const deform::Skeleton& bvh, const OptionalRigMap& model_map,
                          const OptionalRigMap& bvh_map, float model_floor);
  // Per clip frame, how far the body must come down at least so that the knees the clip rests
  // on its floor (motion/clip_resting_knees.h) rest on the model's: measured on the lifted
  // poses (the lower of the body floor's lowest knee and hips samples, the thighs carrying the
  // kneecap's skin, above a part's contact height) over `lowered`, the drop asked for so far;
  // not on frames the body floor lifts (another part is down already); empty where nothing
  // more is needed.
  std::vector<float> lower_resting_knees(const std::vector<float>& lowered) const;
  // bvh_local: rotations and translations of every BVH joint (motion_->joints.size()).
  deform::Pose retarget(std::span<const glm::quat> bvh_local,
                        std::span<const glm::vec3> bvh_translation, bool keep_root_rest) const;
  // The pose of clip frame `frame` retargeted, its root held where the back or hips rest
  // (motion/body_contacts.h), before foot planting.
  deform::Pose unplanted_pose_at_frame(int frame) const;
  // The pose of clip frame `frame` with the root held, the feet planted and the limbs resting
  // on the floor held, before the body floor lifts it; lifted (pose_at_frame).
  deform::Pose feet_planted_pose_at_frame(int frame) const;
  deform::Pose lifted_pose_at_frame(int frame) const;
  // The body floor's lift and arm raise, and the holds of the raised arms (raised again where
  // a hold dipped one): the last steps of a pose.
  void lift_and_raise(double seconds, deform::Pose& pose) const;
  // The shoulder rhythm (see the header): clavicles the clip leaves still follow the arm.
  struct ShoulderRhythm {
    int clavicle = -1, upper = -1, chest = -1;
    glm::vec3 arm_bone{0.0f}, clavicle_bone{0.0f}, chest_up{0.0f};  // in their joints' frames
    float rest_elevation = 0.0f;  // the model's rest arm from straight down, radians
  };
  // Inman's 2:1: a third of the arm's elevation is the shoulder girdle's.
  static constexpr float kShoulderRhythm = 1.0f / 3.0f;
  static constexpr float kLargestClavicleTurn = 0.7854f;  // 45°
  // A model clavicle or hip link within 5° of the clip's is the clip's: aligned and driven like
  // a limb.
  static constexpr float kSameGirdle = 0.9961947f;  // cos(5°)
  // A clip's lower ankle standing higher than this share of its straight legs is not on its
  // floor (sitting on a stool, hanging, or a floor elsewhere than y = 0).
  static constexpr float kHighestStanceAnkle = 0.25f;
  // Rest poses that face within 10° of each other face the same way: their rest poses differ
  // (arms or feet turned a little), not the way their bodies were built.
  static constexpr float kSameFacingDegrees = 10.0f;
  // keeps_parent_angle: per model joint, a girdle bone set otherwise than the clip's.
  void find_shoulder_rhythms(const deform::RigMap& model_map,
                             const std::vector<glm::vec3>& model_world,
                             const std::vector<bool>& keeps_parent_angle);
  bool clip_joint_moves(int clip_joint) const;
  void apply_shoulder_rhythms(deform::Pose& pose, std::vector<glm::quat>& world) const;

  Retargeter(std::shared_ptr<const Clip> motion, deform::Skeleton skeleton,
             const JointNameMap& name_map, float model_floor);

  std::shared_ptr<const Clip> motion_;  // never null
  deform::Skeleton skeleton_;
  std::vector<JointMatch> matches_;
  std::vector<int> bvh_of_model_;                   // per model joint
  std::vector<int> model_of_bvh_;                   // per BVH joint
  std::vector<bool> driven_;                        // per model joint: matched and driven
  glm::quat facing_turn_{1.0f, 0.0f, 0.0f, 0.0f};   // F: about the vertical (Y)
  std::vector<glm::quat> alignment_;                // A_m per model joint
  std::vector<glm::quat> world_rest_;               // W_m(rest) per model joint
  std::vector<glm::quat> clip_world_rest_inverse_;  // W_b(rest)^-1 per clip joint
  int bvh_pelvis_ = 0, model_pelvis_ = 0;
  glm::vec3 model_pelvis_rest_{0.0f};
  float root_scale_ = 1.0f;
  // The clip's floor, its standing ankle above it and its hip height (compute_root_scale);
  // the hip height 0 where the clip has no floor to stand on (no whole legs, or sitting).
  float clip_floor_ = 0.0f, clip_ankle_height_ = 0.0f, clip_hip_height_ = 0.0f;
  float model_hip_height_ = 0.0f;
  OptionalRigMap model_map_;
  std::optional<FootPlanting> planting_;
  std::optional<BodyFloor> body_floor_;            // with planting_: no part below the floor
  std::optional<BodyContacts> body_contacts_;      // with planting_: parts resting held
  std::optional<BodyContacts> measured_contacts_;  // Feet::kPlantedOnly: found, not held
  std::vector<ShoulderRhythm> shoulder_rhythms_;
  std::vector<std::string> warnings_;
};

}  // namespace sweepd::motion
