// Key-ellipse edits JSON (deform/edits/angle_driven_key_edits.h): the file a user writes to correct
// key ellipses at chosen joint angles (paper §4.2), read for `sweepctl edit` and written back out.
// Sweeps are named by body part and joints by name; keys are numbered along the sweep, root
// first (`sweepctl bind MODEL` lists each sweep's keys as it binds).
//
// Format (offset, rotation and scale are optional: 0, 0 and 1 when left out):
//   {
//     "edits": [
//       {
//         "part": "left arm",          // torso, neck, left arm, right arm, left leg, right leg
//         "key": 1,                    // key index in that sweep
//         "joint": "LeftArm",          // the joint whose turn from rest (degrees) drives it
//         "samples": [                 // angles > 0, distinct; 0° is the rest: no correction
//           {"angle": 120,
//            "offset": [0, 0.01, 0],   // metres, in the key's frame (a axis, b axis, normal)
//            "rotation": [0, 0, 30],   // rotation vector, degrees, in the key's frame
//            "scale": [1.0, 1.1]}      // factors of the half-axes a, b (> 0)
//         ]
//       }
//     ]
//   }
#pragma once

#include <filesystem>

#include "deform/binding/bound_model.h"
#include "deform/edits/angle_driven_key_edits.h"

namespace sweepd::io {

// Reads edits for `bound` and validates them (deform::validate). Throws LoadError naming the file
// and the problem: not JSON, a missing field, an unknown part or joint name, a key or value out
// of range.
deform::KeyEllipseEdits load_key_ellipse_edits_json(const std::filesystem::path& path,
                                                    const deform::BoundModel& bound);

// Writes edits for `bound` in the format above. Throws std::runtime_error naming the file when it
// cannot be written.
void save_key_ellipse_edits_json(const deform::KeyEllipseEdits& edits,
                                 const deform::BoundModel& bound,
                                 const std::filesystem::path& path);

}  // namespace sweepd::io
