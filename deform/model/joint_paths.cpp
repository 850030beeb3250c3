#include "deform/model/joint_paths.h"

#include <algorithm>

namespace sweepd::deform {

namespace {
bool in_range(const Skeleton& skeleton, int j) { return j >= 0 && j < skeleton.size(); }
// The parent of j, or -1 for a root and for a parent that breaks the parents-first order (so
// every walk up strictly decreases the index and ends, even on an invalid skeleton).
int parent_of(const Skeleton& skeleton, int j) {
  const int parent = skeleton.joints[j].parent;
  return parent < j ? parent : -1;
}
}  // namespace

bool is_strict_ancestor(const Skeleton& skeleton, int ancestor, int joint) {
  if (!in_range(skeleton, ancestor) || !in_range(skeleton, joint)) return false;
  for (int j = parent_of(skeleton, joint); j >= ancestor; j = parent_of(skeleton, j))
    if (j == ancestor) return true;
  return false;
}

std::vector<int> path_down(const Skeleton& skeleton, int ancestor, int joint) {
  if (!in_range(skeleton, ancestor) || !in_range(skeleton, joint)) return {};
  std::vector<int> path;
  for (int j = joint; j >= ancestor; j = parent_of(skeleton, j)) {
    path.push_back(j);
    if (j == ancestor) {
      std::reverse(path.begin(), path.end());
      return path;
    }
  }
  return {};
}

int common_ancestor(const Skeleton& skeleton, int a, int b) {
  if (!in_range(skeleton, a) || !in_range(skeleton, b)) return -1;
  // Parents-first order: the larger index is never above the smaller one, so lift it.
  while (a != b && a >= 0 && b >= 0) {
    if (a > b)
      a = parent_of(skeleton, a);
    else
      b = parent_of(skeleton, b);
  }
  return a == b ? a : -1;
}

}  // namespace sweepd::deform
