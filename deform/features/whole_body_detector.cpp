#include "deform/features/whole_body_detector.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "deform/features/triangle_intersection.h"
#include "deform/simd/float_lanes.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {
namespace {

// One lane per triangle of a leaf (4: one SSE/NEON register, deform/simd/float_lanes.h).
static_assert(WholeBodyDetector::kLeafSize == 4, "a leaf's triangles fill one FloatLanes");
typedef std::int32_t IntLanes __attribute__((vector_size(16)));

// 10 bits of x, y, z interleaved.
std::uint32_t spread_bits(std::uint32_t v) {
  v = (v | (v << 16)) & 0x030000FFu;
  v = (v | (v << 8)) & 0x0300F00Fu;
  v = (v | (v << 4)) & 0x030C30C3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

constexpr TriangleBox kEmptyBox{glm::vec3(INFINITY), glm::vec3(-INFINITY)};
using NodeBox = WholeBodyDetector::NodeBox;
constexpr NodeBox kEmptyNode{{INFINITY, INFINITY, INFINITY, 0.0f},
                             {-INFINITY, -INFINITY, -INFINITY, 0.0f}};

TriangleBox merged(const TriangleBox& a, const TriangleBox& b) {
  return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)};
}

// Bit k set when lane k is true (lanes are all ones or all zeros).
unsigned lane_bits(IntLanes lanes) {
#if defined(__SSE__)
  return static_cast<unsigned>(_mm_movemask_ps(reinterpret_cast<__m128>(lanes)));
#else
  return (lanes[0] & 1u) | (lanes[1] & 2u) | (lanes[2] & 4u) | (lanes[3] & 8u);
#endif
}

// boxes_overlap of two nodes, lane by lane with one branch (the descent's outcomes are
// unpredictable, so six branches cost more than the compares).
bool nodes_overlap(const NodeBox& a, const NodeBox& b) {
  return lane_bits((load_lanes(a.lo) <= load_lanes(b.hi)) &
                   (load_lanes(b.lo) <= load_lanes(a.hi))) == 15u;
}

NodeBox node_of(const TriangleBox& box) {
  return {{box.lo.x, box.lo.y, box.lo.z, 0.0f}, {box.hi.x, box.hi.y, box.hi.z, 0.0f}};
}

NodeBox merged(const NodeBox& a, const NodeBox& b) {
  NodeBox out;
  for (int k = 0; k < 4; ++k) {
    out.lo[k] = std::min(a.lo[k], b.lo[k]);
    out.hi[k] = std::max(a.hi[k], b.hi[k]);
  }
  return out;
}

}  // namespace

void WholeBodyDetector::build_layout(std::span<const glm::vec3> positions,
                                     std::span<const std::uint32_t> indices,
                                     std::span<const std::uint32_t> triangles) {
  glm::vec3 lo(INFINITY), hi(-INFINITY);
  for (std::uint32_t t : triangles) {
    const TriangleBox box = triangle_box(positions, indices, t);
    lo = glm::min(lo, box.lo);
    hi = glm::max(hi, box.hi);
  }
  const glm::vec3 scale = 1023.0f / glm::max(hi - lo, glm::vec3(1e-30f));
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keyed(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const TriangleBox box = triangle_box(positions, indices, triangles[i]);
    glm::vec3 c = ((box.lo + box.hi) * 0.5f - lo) * scale;
    if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z)) c = glm::vec3(0.0f);
    const glm::uvec3 cell(glm::clamp(c, glm::vec3(0.0f), glm::vec3(1023.0f)));
    keyed[i] = {(spread_bits(cell.x) << 2) | (spread_bits(cell.y) << 1) | spread_bits(cell.z),
                triangles[i]};
  }
  std::sort(keyed.begin(), keyed.end());
  order_.resize(triangles.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order_[i] = keyed[i].second;
  leaf_count_ = static_cast<std::uint32_t>((triangles.size() + kLeafSize - 1) / kLeafSize);
  leaf_base_ = 1;
  height_ = 0;
  while (leaf_base_ < leaf_count_) leaf_base_ *= 2, ++height_;
  nodes_.assign(2 * leaf_base_, kEmptyNode);
  leaves_.resize(leaf_count_);
  built_triangles_ = triangles.data();
  built_size_ = triangles.size();
  built_indices_ = indices.data();
}

void WholeBodyDetector::refit(std::span<const glm::vec3> positions,
                              std::span<const std::uint32_t> indices, int threads) {
  run_in_vertex_blocks(leaf_count_, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t leaf = begin; leaf < end; ++leaf) {
      LeafLanes& lanes = leaves_[leaf];
      TriangleBox box = kEmptyBox;
      for (std::size_t k = 0; k < kLeafSize; ++k) {
        const std::size_t slot = leaf * kLeafSize + k;
        TriangleBox own = kEmptyBox;
        if (slot < order_.size()) {
          const std::uint32_t t = order_[slot];
          own = triangle_box(positions, indices, t);
          for (int c = 0; c < 3; ++c) lanes.vertex[c][k] = indices[3 * t + c];
        } else {
          for (int c = 0; c < 3; ++c) lanes.vertex[c][k] = UINT32_MAX;
        }
        for (int axis = 0; axis < 3; ++axis) {
          lanes.lo[axis][k] = own.lo[axis];
          lanes.hi[axis][k] = own.hi[axis];
        }
        box = merged(box, own);
      }
      nodes_[leaf_base_ + leaf] = node_of(box);
    }
  });
  for (std::uint32_t n = leaf_base_ - 1; n >= 1; --n)
    nodes_[n] = merged(nodes_[2 * n], nodes_[2 * n + 1]);
}

void WholeBodyDetector::leaf_pairs(std::uint32_t a, std::uint32_t b, Context& context) const {
  const LeafLanes& own = leaves_[a];
  const LeafLanes& other = leaves_[b];
  FloatLanes lo[3], hi[3];
  IntLanes vertex[3];
  for (int c = 0; c < 3; ++c) {
    lo[c] = load_lanes(other.lo[c]);
    hi[c] = load_lanes(other.hi[c]);
    std::memcpy(&vertex[c], other.vertex[c], sizeof(vertex[c]));
  }
  const std::size_t own_first = static_cast<std::size_t>(a) * kLeafSize;
  const std::size_t other_first = static_cast<std::size_t>(b) * kLeafSize;
  for (std::size_t i = 0; i < kLeafSize; ++i) {
    // The closed boxes overlap (boxes_overlap, lane by lane; empty lanes never do) ...
    const IntLanes overlap = (own.lo[0][i] <= hi[0]) & (lo[0] <= own.hi[0][i]) &
                             (own.lo[1][i] <= hi[1]) & (lo[1] <= own.hi[1][i]) &
                             (own.lo[2][i] <= hi[2]) & (lo[2] <= own.hi[2][i]);
    // ... and no welded vertex is shared (share_a_vertex).
    IntLanes shared = IntLanes{};
    for (int c = 0; c < 3; ++c) {
      const auto v = static_cast<std::int32_t>(own.vertex[c][i]);
      shared |= (vertex[0] == v) | (vertex[1] == v) | (vertex[2] == v);
    }
    unsigned bits = lane_bits(overlap & ~shared);
    if (a == b) bits &= ~((2u << i) - 1u);  // within one leaf: each pair once, never itself
    for (; bits != 0; bits &= bits - 1) {
      const std::size_t j = static_cast<std::size_t>(__builtin_ctz(bits));
      std::uint32_t s = order_[own_first + i], t = order_[other_first + j];
      if (s > t) std::swap(s, t);
      if (mesh_triangles_intersect(context.positions, context.indices, s, t))
        context.out.push_back({s, t});
    }
  }
}

void WholeBodyDetector::self(std::uint32_t node, std::uint32_t height, Context& context) const {
  // The tree's leaves past the list's end are empty: nothing under them.
  if ((static_cast<std::uint64_t>(node) << height) - leaf_base_ >= leaf_count_) return;
  if (height == 0) return leaf_pairs(node - leaf_base_, node - leaf_base_, context);
  self(2 * node, height - 1, context);
  self(2 * node + 1, height - 1, context);
  if (nodes_overlap(nodes_[2 * node], nodes_[2 * node + 1]))
    cross(2 * node, 2 * node + 1, height - 1, context);
}

void WholeBodyDetector::cross(std::uint32_t a, std::uint32_t b, std::uint32_t height,
                              Context& context) const {
  if (height == 0) return leaf_pairs(a - leaf_base_, b - leaf_base_, context);
  // The four child pairs tested before descending, without a branch per test (their outcomes
  // are unpredictable); then one call per overlapping pair.
  const NodeBox* as = &nodes_[2 * a];
  const NodeBox* bs = &nodes_[2 * b];
  unsigned bits = static_cast<unsigned>(nodes_overlap(as[0], bs[0])) |
                  static_cast<unsigned>(nodes_overlap(as[0], bs[1])) << 1 |
                  static_cast<unsigned>(nodes_overlap(as[1], bs[0])) << 2 |
                  static_cast<unsigned>(nodes_overlap(as[1], bs[1])) << 3;
  for (; bits != 0; bits &= bits - 1) {
    const unsigned k = static_cast<unsigned>(__builtin_ctz(bits));
    const std::uint32_t child_a = 2 * a + (k >> 1), child_b = 2 * b + (k & 1);
    if (height == 1)
      leaf_pairs(child_a - leaf_base_, child_b - leaf_base_, context);
    else
      cross(child_a, child_b, height - 1, context);
  }
}

void WholeBodyDetector::split_tasks(std::size_t wanted) {
  tasks_.assign(1, {1u, 1u, height_});
  while (tasks_.size() < wanted && tasks_.front().height > 0) {
    next_tasks_.clear();
    auto add_cross = [&](std::uint32_t a, std::uint32_t b, std::uint32_t height) {
      if (nodes_overlap(nodes_[a], nodes_[b])) next_tasks_.push_back({a, b, height});
    };
    for (const Task& task : tasks_) {
      const std::uint32_t h = task.height - 1;
      if (task.a == task.b) {
        next_tasks_.push_back({2 * task.a, 2 * task.a, h});
        next_tasks_.push_back({2 * task.a + 1, 2 * task.a + 1, h});
        add_cross(2 * task.a, 2 * task.a + 1, h);
        continue;
      }
      for (std::uint32_t a : {2 * task.a, 2 * task.a + 1})
        for (std::uint32_t b : {2 * task.b, 2 * task.b + 1}) add_cross(a, b, h);
    }
    tasks_.swap(next_tasks_);
  }
}

void WholeBodyDetector::detect(std::span<const glm::vec3> positions,
                               std::span<const std::uint32_t> indices,
                               std::span<const std::uint32_t> triangles,
                               std::vector<TrianglePair>& pairs, int threads) {
  pairs.clear();
  if (triangles.size() < 2) return;
  if (triangles.data() != built_triangles_ || triangles.size() != built_size_ ||
      indices.data() != built_indices_)
    build_layout(positions, indices, triangles);
  refit(positions, indices, threads);
  const std::size_t workers = static_cast<std::size_t>(std::max(threads, 1));
  found_.resize(std::max(found_.size(), workers));
  // Many more tasks than threads, taken as they finish: the body's contact is uneven.
  split_tasks(workers == 1 ? 1 : 64 * workers);
  std::atomic<std::size_t> next{0};
  run_in_vertex_blocks(workers, static_cast<int>(workers), [&](std::size_t begin, std::size_t) {
    Context context{positions, indices, found_[begin]};
    context.out.clear();
    for (std::size_t k = next++; k < tasks_.size(); k = next++) {
      const Task& task = tasks_[k];
      if (task.a == task.b)
        self(task.a, task.height, context);
      else
        cross(task.a, task.b, task.height, context);
    }
  });
  for (std::size_t w = 0; w < workers; ++w)
    pairs.insert(pairs.end(), found_[w].begin(), found_[w].end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
}

}  // namespace sweepd::deform
