#include "motion/range_of_motion.h"

#include <cmath>
#include <functional>
#include <map>

#include "motion/shortest_arc.h"

namespace sweepd::motion {
namespace {

using deform::ArmJoints;
using deform::LegJoints;

constexpr float kDegree = static_cast<float>(M_PI / 180.0);

// A pose as turns in the rest world frame, per joint (composed when a joint gets several).
using Turns = std::map<int, glm::quat>;

struct Move {
  std::string name;
  Turns turns;
};

class MoveBuilder {
 public:
  MoveBuilder(const deform::Skeleton& skeleton, const deform::RigMap& map)
      : skeleton_(skeleton), map_(map), world_(skeleton.world_rest_matrices()),
        axes_(deform::rest_body_axes(map, world_)) {}

  std::vector<Move> moves() {
    std::vector<Move> out;
    auto add = [&](std::string name, const std::function<void(Turns&)>& build) {
      Turns turns;
      build(turns);
      if (!turns.empty()) out.push_back({std::move(name), std::move(turns)});
    };
    const glm::vec3 up = axes_.up, forward = axes_.forward;
    // Legs, both sides mirrored (side s: +1 left, -1 right; outward = s * left).
    auto legs = [&](const std::function<void(Turns&, const LegJoints&, float)>& each) {
      return [&, each](Turns& t) {
        each(t, map_.left_leg, 1.0f);
        each(t, map_.right_leg, -1.0f);
      };
    };
    auto thigh = [&](Turns& t, const LegJoints& leg, glm::vec3 toward, float degrees) {
      if (leg.upper >= 0 && leg.lower >= 0) swing(t, leg.upper, leg.lower, toward, degrees);
    };
    auto knee = [&](Turns& t, const LegJoints& leg, float degrees) {
      if (leg.lower >= 0 && leg.foot >= 0) swing(t, leg.lower, leg.foot, -forward, degrees);
    };
    auto ankle = [&](Turns& t, const LegJoints& leg, glm::vec3 toward, float degrees) {
      if (leg.foot >= 0) swing(t, leg.foot, leg.toe, toward, degrees);
    };
    add("hip flexion 130°", legs([&](Turns& t, const LegJoints& l, float) {
          thigh(t, l, forward, 130);
        }));
    add("hip extension 30°", legs([&](Turns& t, const LegJoints& l, float) {
          thigh(t, l, -forward, 30);
        }));
    add("hip abduction 45°", legs([&](Turns& t, const LegJoints& l, float s) {
          thigh(t, l, s * axes_.left, 45);
        }));
    add("hip adduction 20°", legs([&](Turns& t, const LegJoints& l, float s) {
          thigh(t, l, -s * axes_.left, 20);
        }));
    for (const float degrees : {40.0f, -40.0f})
      add(std::string("hip rotation ") + (degrees > 0 ? "outward" : "inward") + " 40°",
          legs([&, degrees](Turns& t, const LegJoints& l, float s) {
            if (l.upper >= 0 && l.lower >= 0) twist(t, l.upper, l.lower, s * degrees);
          }));
    add("knee flexion 150°", legs([&](Turns& t, const LegJoints& l, float) { knee(t, l, 150); }));
    add("ankle dorsiflexion 20°", legs([&](Turns& t, const LegJoints& l, float) {
          ankle(t, l, up, 20);
        }));
    add("ankle plantar flexion 45°", legs([&](Turns& t, const LegJoints& l, float) {
          ankle(t, l, -up, 45);
        }));
    // The spine and neck, spread over their joints.
    const std::vector<int> spine(map_.torso.chain.begin() + (map_.torso.chain.empty() ? 0 : 1),
                                 map_.torso.chain.end());
    const std::vector<int>& neck = map_.neck.chain;
    auto bend = [this](const std::vector<int>& chain, glm::vec3 toward, float degrees) {
      return [this, chain, toward, degrees](Turns& t) { spread(t, chain, toward, degrees); };
    };
    auto turn = [up](const std::vector<int>& chain, float degrees) {
      return [chain, up, degrees](Turns& t) {
        for (int j : chain)
          compose(t, j, glm::angleAxis(degrees * kDegree / static_cast<float>(chain.size()), up));
      };
    };
    // Flexion, extension, side bends and twists; the spine's over its joints above the pelvis.
    struct Bends {
      const char* name;
      const std::vector<int>& chain;
      float flexion, extension, side, twist;
    };
    for (const Bends& b : {Bends{"spine", spine, 70, 30, 35, 45}, Bends{"neck", neck, 45, 45, 40, 70}}) {
      const std::string name = b.name;
      auto degrees = [](float d) { return " " + std::to_string(static_cast<int>(d)) + "°"; };
      add(name + " flexion" + degrees(b.flexion), bend(b.chain, forward, b.flexion));
      add(name + " extension" + degrees(b.extension), bend(b.chain, -forward, b.extension));
      add(name + " side bend left" + degrees(b.side), bend(b.chain, axes_.left, b.side));
      add(name + " side bend right" + degrees(b.side), bend(b.chain, -axes_.left, b.side));
      add(name + " twist left" + degrees(b.twist), turn(b.chain, b.twist));
      add(name + " twist right" + degrees(b.twist), turn(b.chain, -b.twist));
    }
    // Arms, both sides mirrored: the upper arm to directions of the body.
    auto arms = [&](const std::function<void(Turns&, const ArmJoints&, float)>& each) {
      return [&, each](Turns& t) {
        each(t, map_.left_arm, 1.0f);
        each(t, map_.right_arm, -1.0f);
      };
    };
    // d(s): a direction of the body for side s, as (left, up, forward) components.
    struct Direction {
      const char* name;
      float out, up, forward;
    };
    const Direction directions[] = {
        {"arms down", 0.25f, -1.0f, 0.0f},
        {"arms out to the side", 1.0f, 0.0f, 0.0f},
        {"arms overhead", 0.25f, 1.0f, 0.0f},
        {"arms forward", 0.0f, 0.0f, 1.0f},
        {"arms forward and up", 0.0f, 1.0f, 0.3f},
        {"arms across the chest", -0.8f, 0.0f, 0.7f},
        {"arms back at shoulder height", 0.6f, 0.0f, -0.8f},
        {"arms behind the back", -0.3f, -0.7f, -0.5f},
    };
    auto body_direction = [&](const Direction& d, float s) {
      return glm::normalize(s * d.out * axes_.left + d.up * up + d.forward * forward);
    };
    auto upper_arm_to = [&](Turns& t, const ArmJoints& arm, glm::vec3 target) {
      if (arm.upper < 0 || arm.lower < 0) return;
      const glm::vec3 from = bone(arm.upper, arm.lower);
      compose(t, arm.upper, shortest_arc(from, glm::normalize(target)));
    };
    for (const Direction& d : directions)
      add(d.name, arms([&, d](Turns& t, const ArmJoints& a, float s) {
            upper_arm_to(t, a, body_direction(d, s));
          }));
    auto shrug = [&](glm::vec3 toward, float degrees) {
      return arms([&, toward, degrees](Turns& t, const ArmJoints& a, float) {
        if (a.clavicle >= 0 && a.upper >= 0) swing(t, a.clavicle, a.upper, toward, degrees);
      });
    };
    add("clavicle shrug 25°", shrug(up, 25));
    add("clavicle forward 20°", shrug(forward, 20));
    add("clavicle back 15°", shrug(-forward, 15));
    auto elbow = [&](Turns& t, const ArmJoints& a, float degrees) {
      if (a.lower >= 0) swing(t, a.lower, a.hand, forward, degrees);
    };
    add("elbow flexion 150°", arms([&](Turns& t, const ArmJoints& a, float) { elbow(t, a, 150); }));
    for (const float degrees : {80.0f, -80.0f})
      add(std::string("forearm twist ") + (degrees > 0 ? "outward" : "inward") + " 80°",
          arms([&, degrees](Turns& t, const ArmJoints& a, float s) {
            if (a.lower >= 0) twist(t, a.lower, a.hand, s * degrees);
          }));
    auto wrist = [&](glm::vec3 toward, float degrees) {
      return arms([&, toward, degrees](Turns& t, const ArmJoints& a, float) {
        if (a.hand >= 0) swing(t, a.hand, -1, toward, degrees);
      });
    };
    add("wrist up 60°", wrist(up, 60));
    add("wrist down 60°", wrist(-up, 60));
    add("wrist forward 30°", wrist(forward, 30));
    add("wrist back 30°", wrist(-forward, 30));
    // Combined.
    for (const float s : {1.0f, -1.0f}) {
      const LegJoints& leg = s > 0 ? map_.left_leg : map_.right_leg;
      add(std::string(s > 0 ? "left" : "right") + " knee to chest", [&, leg](Turns& t) {
        thigh(t, leg, forward, 130);
        knee(t, leg, 150);
      });
    }
    add("deep squat", [&](Turns& t) {
      legs([&](Turns& u, const LegJoints& l, float) {
        thigh(u, l, forward, 120);
        knee(u, l, 145);
        ankle(u, l, up, 25);
      })(t);
      spread(t, spine, forward, 30);
      arms([&](Turns& u, const ArmJoints& a, float) {
        upper_arm_to(u, a, forward);
      })(t);
    });
    add("kneeling upright", legs([&](Turns& t, const LegJoints& l, float) {
          knee(t, l, 90);
          ankle(t, l, -up, 40);
        }));
    add("kneeling on the heels", legs([&](Turns& t, const LegJoints& l, float) {
          thigh(t, l, forward, 80);
          knee(t, l, 150);
          ankle(t, l, -up, 45);
        }));
    add("lunge", [&](Turns& t) {
      thigh(t, map_.left_leg, forward, 90);
      knee(t, map_.left_leg, 90);
      thigh(t, map_.right_leg, -forward, 20);
      knee(t, map_.right_leg, 90);
    });
    add("reach overhead with a side bend", [&](Turns& t) {
      upper_arm_to(t, map_.left_arm, body_direction(directions[2], 1.0f));
      upper_arm_to(t, map_.right_arm, body_direction(directions[0], -1.0f));
      spread(t, spine, -axes_.left, 30);
    });
    add("twist with the arms across the chest", [&](Turns& t) {
      arms([&](Turns& u, const ArmJoints& a, float s) {
        upper_arm_to(u, a, body_direction(directions[5], s));
        elbow(u, a, 90);
      })(t);
      turn(spine, 40)(t);
    });
    add("hands behind the head", arms([&](Turns& t, const ArmJoints& a, float s) {
          upper_arm_to(t, a, body_direction(directions[1], s) * 0.5f + up * 0.5f);
          elbow(t, a, 150);
        }));
    return out;
  }

  // A move's turns as the local rotations of the joints they touch (rest elsewhere).
  std::vector<glm::quat> local_rotations(const Turns& turns) const {
    std::vector<glm::quat> local(skeleton_.joints.size());
    for (std::size_t j = 0; j < local.size(); ++j) local[j] = skeleton_.joints[j].rest_rotation;
    for (const auto& [joint, turn] : turns) {
      const glm::quat w = world_rotation(joint);
      local[joint] = glm::normalize(skeleton_.joints[joint].rest_rotation *
                                    (glm::inverse(w) * turn * w));
    }
    return local;
  }

 private:
  glm::vec3 position(int joint) const { return glm::vec3(world_[joint][3]); }
  glm::quat world_rotation(int joint) const {
    const glm::mat3 m(world_[joint]);
    return glm::normalize(glm::quat_cast(
        glm::mat3(glm::normalize(m[0]), glm::normalize(m[1]), glm::normalize(m[2]))));
  }

  // The rest direction of the bone starting at `joint`: towards `next` (a role joint below it),
  // else its first child, else its parent's bone (a chain's last joint).
  glm::vec3 bone(int joint, int next) const {
    if (next < 0) {
      const std::vector<int> children = skeleton_.children(joint);
      for (int child : children)
        if (glm::length(position(child) - position(joint)) > 1e-6f) {
          next = child;
          break;
        }
    }
    if (next >= 0) {
      const glm::vec3 d = position(next) - position(joint);
      if (glm::length(d) > 1e-6f) return glm::normalize(d);
    }
    const int parent = skeleton_.joints[joint].parent;
    return parent >= 0 ? bone(parent, joint) : axes_.up;
  }

  static void compose(Turns& turns, int joint, glm::quat turn) {
    const auto found = turns.find(joint);
    turns[joint] = found == turns.end() ? turn : glm::normalize(turn * found->second);
  }

  // Swings the bone at `joint` (towards `next`) by `degrees` towards `toward`: about the axis
  // normal to both. A bone along `toward` swings about the body's left axis instead.
  void swing(Turns& turns, int joint, int next, glm::vec3 toward, float degrees) const {
    swing_direction(turns, joint, bone(joint, next), toward, degrees);
  }
  void swing_direction(Turns& turns, int joint, glm::vec3 d, glm::vec3 toward,
                       float degrees) const {
    glm::vec3 axis = glm::cross(d, toward);
    if (glm::length(axis) < 0.2f) axis = glm::cross(d, glm::cross(axes_.left, d));
    if (glm::length(axis) < 1e-4f) return;
    compose(turns, joint, glm::angleAxis(degrees * kDegree, glm::normalize(axis)));
  }
  void twist(Turns& turns, int joint, int next, float degrees) const {
    compose(turns, joint, glm::angleAxis(degrees * kDegree, bone(joint, next)));
  }
  // A bend of the body's up direction towards `toward`, spread evenly over the chain's joints.
  void spread(Turns& turns, const std::vector<int>& chain, glm::vec3 toward, float degrees) const {
    for (int j : chain)
      swing_direction(turns, j, axes_.up, toward, degrees / static_cast<float>(chain.size()));
  }

  const deform::Skeleton& skeleton_;
  const deform::RigMap& map_;
  std::vector<glm::mat4> world_;
  deform::BodyAxes axes_;
};

// Rest to the peak and back, eased (smoothstep) so the clip plays as motion in a DCC tool.
float ease(int frame_in_move) {
  const float half = kRomFramesPerMove / 2.0f;
  const float x = frame_in_move <= half ? frame_in_move / half : (kRomFramesPerMove - frame_in_move) / half;
  return x * x * (3.0f - 2.0f * x);
}

}  // namespace

const std::string& RangeOfMotion::move_at(int frame) const {
  static const std::string rest = "rest";
  for (const RomMove& move : moves)
    if (frame >= move.first_frame && frame < move.first_frame + kRomFramesPerMove)
      return move.name;
  return rest;
}

RangeOfMotion range_of_motion(const deform::Skeleton& skeleton, const deform::RigMap& map) {
  MoveBuilder builder(skeleton, map);
  const std::vector<Move> moves = builder.moves();
  RangeOfMotion rom;
  Clip& clip = rom.clip;
  for (const deform::Joint& joint : skeleton.joints) {
    ClipJoint c;
    c.name = joint.name;
    c.parent = joint.parent;
    c.offset = joint.rest_translation;
    c.rest_rotation = joint.rest_rotation;
    clip.joints.push_back(std::move(c));
  }
  // One track per joint any move turns, a key at every frame (the eased curve baked).
  std::map<int, KeyframeTrack> tracks;
  for (const Move& move : moves)
    for (const auto& [joint, turn] : move.turns) tracks[joint].joint = joint;
  const int frames = static_cast<int>(moves.size()) * kRomFramesPerMove + 1;
  for (int m = 0; m <= static_cast<int>(moves.size()); ++m) {
    const bool last = m == static_cast<int>(moves.size());
    const std::vector<glm::quat> peak =
        builder.local_rotations(last ? Turns{} : moves[m].turns);
    if (!last)
      rom.moves.push_back({moves[m].name, m * kRomFramesPerMove,
                           m * kRomFramesPerMove + kRomFramesPerMove / 2});
    for (int f = 0; f < (last ? 1 : kRomFramesPerMove); ++f) {
      const int frame = m * kRomFramesPerMove + f;
      const float w = ease(f);
      for (auto& [joint, track] : tracks) {
        const glm::quat q = glm::normalize(
            glm::slerp(skeleton.joints[joint].rest_rotation, peak[joint], w));
        track.times.push_back(static_cast<float>(frame) / kRomFramesPerSecond);
        track.values.insert(track.values.end(), {q.x, q.y, q.z, q.w});
      }
    }
  }
  for (auto& [joint, track] : tracks) clip.tracks.push_back(std::move(track));
  // Set, not derived from the keys (Clip::set_keyframed_timing): the keys' float times are
  // only nearly 1/30 s apart.
  clip.frame_time = 1.0f / kRomFramesPerSecond;
  clip.frame_count = clip.header_frame_count = frames;
  clip.start_time = 0.0f;
  clip.end_time = static_cast<float>(frames - 1) / kRomFramesPerSecond;
  return rom;
}

}  // namespace sweepd::motion
