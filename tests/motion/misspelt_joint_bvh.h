// A BVH clip with a joint that matches nothing on a model, for tests of issue 48 item 4
// ("nothing unmapped in silence"): the text of a CMU clip with a joint "HeadTpo" (a misspelt
// "HeadTop", which the mannequin and the shared male lack) put inside its Head, before the
// Head's End Site. It has no channels, so the frames' rows are unchanged and every other joint
// moves as in the original; retargeting leaves it unmapped and must name it.
//   with_misspelt_joint(text)  the text with the joint, or "" when the text has no Head block
//   kMisspeltJoint             its name
#pragma once

#include <string>

namespace sweepd::test {

inline constexpr const char* kMisspeltJoint = "HeadTpo";

inline std::string with_misspelt_joint(const std::string& bvh) {
  const std::size_t head = bvh.find("JOINT Head");
  if (head == std::string::npos) return "";
  const std::size_t end_site = bvh.find("End Site", head);
  if (end_site == std::string::npos) return "";
  const std::string joint = std::string("JOINT ") + kMisspeltJoint +
                            "\n{\nOFFSET 0 1.5 0\nCHANNELS 0\nEnd Site\n{\nOFFSET 0 1 0\n}\n}\n";
  return bvh.substr(0, end_site) + joint + bvh.substr(end_site);
}

}  // namespace sweepd::test
