// The served model's rest skeleton, from its ModelInfo (protocol 1.1), so a client retargets
// motion onto the model exactly as the library would, without the model's file.
//
//   rest_skeleton(info):            joints in model order (names, parents, rest T/R/S)
//   retarget_onto(info, clip):      motion::Retargeter with the model's floor (lowest rest vertex)
//
// Both throw std::runtime_error when the server sent no rest skeleton (a 1.0 server).
#pragma once

#include "deform/model/skeleton.h"
#include "motion/retarget.h"
#include "protocol/messages.h"

namespace sweepd::client {

deform::Skeleton rest_skeleton(const protocol::ModelInfo& info);

motion::Retargeter retarget_onto(const protocol::ModelInfo& info, motion::Clip clip,
                                 const motion::JointNameMap& name_map = {});

}  // namespace sweepd::client
