#include "gpu/collision.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "deform/features/triangle_intersection.h"
#include "gpu/collision_shaders.h"

namespace sweepd::gpu {
namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kMostLists = 64;             // cached lists; then the cache starts over
constexpr std::size_t kMostSlots = std::size_t{1} << 24;  // cached triangles, all lists
constexpr int kBufferCount = 9;                    // one per CollisionBinding

constexpr CollisionPass kPasses[] = {CollisionPass::kBoxes,      CollisionPass::kBuckets,
                                     CollisionPass::kScatter,    CollisionPass::kCellPairs,
                                     CollisionPass::kNarrowSize, CollisionPass::kNarrow};

}  // namespace

struct CollisionDetector::List {
  std::vector<std::uint32_t> triangles;  // ids, as the caller gave them
  std::vector<std::uint32_t> corners;    // 3 per triangle: its welded indices
  std::uint32_t max_corner = 0;
  std::size_t first_slot = 0;
  std::vector<glm::vec3> computed_at;  // 3 per triangle: corner positions of the computation
  const glm::vec3* source = nullptr;   // the positions buffer it came from
  bool computed = false;               // `pairs` belong to `computed_at`
  bool queued = false;                 // in the next submission
  bool requested = false;              // asked for by this call (its corners were checked)
  bool finite = true;
  float inverse_cell = 1.0f;
  std::vector<deform::TrianglePair> pairs;
};

// GL buffers (one per CollisionBinding) and what each holds.
struct CollisionDetector::Buffers {
  GLuint ids[kBufferCount] = {};
  std::size_t bytes[kBufferCount] = {};
  std::size_t slots = 0, entries = 0, candidates = 0, outputs = 0, buckets = 0;
  GLint uniforms[std::size(kPasses)][6] = {};
};

namespace {

const char* const kUniformNames[6] = {"active_count",   "batch_count",        "bucket_mask",
                                      "entry_capacity", "candidate_capacity", "output_capacity"};

}  // namespace

CollisionDetector::CollisionDetector(const Context& context)
    : gl_(context.gl()), buffers_(std::make_unique<Buffers>()) {
  for (std::size_t p = 0; p < std::size(kPasses); ++p) {
    const std::string source = collision_pass_source(kPasses[p]);
    passes_.push_back(std::make_unique<ShaderProgram>(gl_, "collision", source.c_str()));
    for (int u = 0; u < 6; ++u) buffers_->uniforms[p][u] = passes_[p]->uniform(kUniformNames[u]);
  }
  gl_.GenBuffers(kBufferCount, buffers_->ids);
  throw_on_gl_error(gl_, "collision buffers");
  // Run every pass once, so the driver's code generation (llvmpipe compiles on first dispatch)
  // happens here and not in a caller's frame; then forget the list.
  const glm::vec3 corners[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2f, 0.2f, -1}, {0.3f, 0.2f, 1},
                                {0.2f, 0.3f, 1}};
  const std::uint32_t indices[6] = {0, 1, 2, 3, 4, 5}, ids[2] = {0, 1};
  std::vector<deform::TrianglePair> pairs;
  detect(corners, indices, ids, pairs);
  lists_.clear();
  slots_used_ = 0;
}

CollisionDetector::~CollisionDetector() { gl_.DeleteBuffers(kBufferCount, buffers_->ids); }

std::size_t CollisionDetector::find_or_learn(std::span<const std::uint32_t> indices,
                                             std::span<const std::uint32_t> triangles) {
  const std::size_t mesh_triangles = indices.size() / 3;
  for (std::size_t i = 0; i < lists_.size(); ++i) {
    const List& list = lists_[i];
    if (list.triangles.size() != triangles.size() ||
        !std::equal(triangles.begin(), triangles.end(), list.triangles.begin()))
      continue;
    bool same = true;
    for (std::size_t k = 0; k < triangles.size() && same; ++k) {
      const std::uint32_t t = triangles[k];
      same = t < mesh_triangles && indices[3 * t] == list.corners[3 * k] &&
             indices[3 * t + 1] == list.corners[3 * k + 1] &&
             indices[3 * t + 2] == list.corners[3 * k + 2];
    }
    if (same) return i;
  }
  for (const std::uint32_t t : triangles) {
    if (t >= mesh_triangles)
      throw std::invalid_argument("collision detection: triangle " + std::to_string(t) +
                                  " is not in the mesh (" + std::to_string(mesh_triangles) +
                                  " triangles)");
  }
  if (lists_.size() == kMostLists || slots_used_ + triangles.size() > kMostSlots) {
    lists_.clear();
    slots_used_ = 0;
    ++cache_epoch_;
  }
  List& list = lists_.emplace_back();
  list.triangles.assign(triangles.begin(), triangles.end());
  list.corners.resize(3 * triangles.size());
  for (std::size_t k = 0; k < triangles.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      list.corners[3 * k + c] = indices[3 * triangles[k] + c];
      list.max_corner = std::max(list.max_corner, list.corners[3 * k + c]);
    }
  }
  list.computed_at.resize(3 * triangles.size());
  list.first_slot = slots_used_;
  slots_used_ += triangles.size();
  const std::size_t index = lists_.size() - 1;
  slot_list_.resize(slots_used_);
  std::fill(slot_list_.begin() + static_cast<std::ptrdiff_t>(list.first_slot), slot_list_.end(),
            static_cast<std::uint32_t>(index));
  grow_slots(slots_used_);  // uploads every list's records when it grows, this one's otherwise
  return index;
}

namespace {

// Per slot (welded corners, triangle id): the topology the GPU reads.
void append_records(const std::vector<std::uint32_t>& triangles,
                    const std::vector<std::uint32_t>& corners, std::vector<glm::uvec4>& records) {
  for (std::size_t k = 0; k < triangles.size(); ++k)
    records.emplace_back(corners[3 * k], corners[3 * k + 1], corners[3 * k + 2], triangles[k]);
}

}  // namespace

void CollisionDetector::grow_slots(std::size_t slots) {
  Buffers& b = *buffers_;
  std::vector<glm::uvec4> records;  // allocation only while lists are being learnt
  if (slots > b.slots) {
    b.slots = std::max({slots, 2 * b.slots, std::size_t{4096}});
    for (const List& list : lists_) append_records(list.triangles, list.corners, records);
    records.resize(b.slots);
    allocate(kRecordsBinding, b.slots * sizeof(glm::uvec4), records.data());
    allocate(kBoxesBinding, 2 * b.slots * sizeof(glm::vec4), nullptr);
    // Starting capacities from the slots (a triangle covers 1-8 cells); grown on overflow.
    b.entries = std::max(b.entries, 8 * b.slots);
    allocate(kEntriesBinding, b.entries * sizeof(glm::uvec4), nullptr);
    allocate(kSortedBinding, b.entries * sizeof(glm::uvec4), nullptr);
    b.candidates = std::max(b.candidates, 4 * b.slots);
    allocate(kCandidatesBinding, b.candidates * sizeof(glm::uvec2), nullptr);
    b.outputs = std::max(b.outputs, b.slots);
    allocate(kOutputBinding, kOutputHeaderWords * 4 + b.outputs * sizeof(glm::uvec2), nullptr);
    // Up to 4 per slot (a submission uses about 4 per triangle it holds), at most 2^25
    // (32,768 workgroups of the bucket pass).
    b.buckets = std::min(std::bit_ceil(4 * b.slots), std::size_t{1} << 25);
    const std::vector<std::uint32_t> zeros(2 * b.buckets, 0u);  // counts start at zero
    allocate(kBucketsBinding, zeros.size() * sizeof(std::uint32_t), zeros.data());
  } else {
    const List& list = lists_.back();
    append_records(list.triangles, list.corners, records);
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b.ids[kRecordsBinding]);
    gl_.BufferSubData(GL_SHADER_STORAGE_BUFFER,
                      static_cast<GLintptr>(list.first_slot * sizeof(glm::uvec4)),
                      static_cast<GLsizeiptr>(records.size() * sizeof(glm::uvec4)),
                      records.data());
  }
  throw_on_gl_error(gl_, "collision topology upload");
}

bool CollisionDetector::refresh(List& list, std::span<const glm::vec3> positions) {
  if (list.max_corner >= positions.size())
    throw std::invalid_argument("collision detection: a triangle uses vertex " +
                                std::to_string(list.max_corner) + " but positions hold " +
                                std::to_string(positions.size()));
  const glm::vec3* p = positions.data();
  if (list.computed) {
    std::size_t k = 0;
    while (k < list.corners.size() && p[list.corners[k]] == list.computed_at[k]) ++k;
    if (k == list.corners.size()) return false;
  }
  list.computed = false;
  double extent_sum = 0.0;
  float extent_max = 0.0f;
  bool finite = true;
  for (std::size_t t = 0; t < list.triangles.size(); ++t) {
    const glm::vec3 a = p[list.corners[3 * t]], b = p[list.corners[3 * t + 1]],
                    c = p[list.corners[3 * t + 2]];
    list.computed_at[3 * t] = a, list.computed_at[3 * t + 1] = b, list.computed_at[3 * t + 2] = c;
    const glm::vec3 size = glm::max(a, glm::max(b, c)) - glm::min(a, glm::min(b, c));
    const float extent = std::max(size.x, std::max(size.y, size.z));
    finite = finite && std::isfinite(extent);
    extent_sum += extent;
    extent_max = std::max(extent_max, extent);
  }
  list.finite = finite;
  // Twice the mean of the boxes' largest extents (measured on llvmpipe: against the mean, half
  // the (triangle, cell) entries for a few more pairs per cell, 30% less time), and no box over
  // 17 cells along an axis.
  const float cell = std::max(
      {2.0f * static_cast<float>(extent_sum / static_cast<double>(list.triangles.size())),
       extent_max / 16.0f, 1e-20f});
  list.inverse_cell = 1.0f / cell;
  return true;
}

void CollisionDetector::queue_if_stale(std::size_t index, std::span<const glm::vec3> positions) {
  List& list = lists_[index];
  if (list.queued || !refresh(list, positions)) return;
  list.queued = true;
  batch_.push_back(index);
}

void CollisionDetector::detect(std::span<const glm::vec3> positions,
                               std::span<const std::uint32_t> indices,
                               std::span<const std::uint32_t> triangles,
                               std::vector<deform::TrianglePair>& pairs) {
  const std::span<const std::uint32_t> lists[1] = {triangles};
  detect_all(positions, indices, lists, std::span(&pairs, 1));
}

void CollisionDetector::detect_all(std::span<const glm::vec3> positions,
                                   std::span<const std::uint32_t> indices,
                                   std::span<const std::span<const std::uint32_t>> lists,
                                   std::span<std::vector<deform::TrianglePair>> pairs) {
  const Clock::time_point started = Clock::now();
  timings_ = {};
  stats_ = {};
  if (pairs.size() != lists.size())
    throw std::invalid_argument("collision detection: " + std::to_string(lists.size()) +
                                " triangle lists but " + std::to_string(pairs.size()) +
                                " pair outputs");
  std::size_t total = 0;
  for (const auto& list : lists) total += list.size();
  if (lists.size() > kMostLists || total > kMostSlots)
    throw std::invalid_argument("collision detection: at most " + std::to_string(kMostLists) +
                                " lists and " + std::to_string(kMostSlots) +
                                " triangles per call, not " + std::to_string(lists.size()) +
                                " and " + std::to_string(total));
  // Find (or learn) every list; learning may start the cache over: then find them all again.
  constexpr std::size_t kNone = ~std::size_t{0};
  for (;;) {
    const std::uint64_t epoch = cache_epoch_;
    asked_.clear();
    for (const auto& list : lists) asked_.push_back(list.size() < 2 ? kNone : find_or_learn(indices, list));
    if (cache_epoch_ == epoch) break;
  }
  batch_.clear();
  auto forget_flags = [this] {
    for (const std::size_t i : asked_)
      if (i != kNone) lists_[i].requested = false;
    for (const std::size_t i : batch_) lists_[i].queued = false;
  };
  try {
    for (const std::size_t i : asked_) {
      if (i == kNone) continue;
      lists_[i].requested = true;
      queue_if_stale(i, positions);
    }
    if (!batch_.empty()) {
      // Lists computed from this positions buffer before, stale too, and small: ride along.
      const std::size_t small = indices.size() / 12;
      for (std::size_t j = 0; j < lists_.size(); ++j) {
        const List& list = lists_[j];
        if (list.queued || list.source != positions.data() || list.triangles.size() > small ||
            list.triangles.size() < 2 || list.max_corner >= positions.size())
          continue;
        queue_if_stale(j, positions);
      }
      run_batch(positions, indices);
    }
  } catch (...) {
    forget_flags();
    throw;
  }
  forget_flags();
  for (std::size_t l = 0; l < lists.size(); ++l) {
    if (asked_[l] == kNone) {
      pairs[l].clear();
      continue;
    }
    const List& list = lists_[asked_[l]];
    pairs[l].assign(list.pairs.begin(), list.pairs.end());
  }
  const Clock::time_point done = Clock::now();
  timings_.upload = (stats_.submissions ? first_dispatch_ : done) - started;
  if (stats_.submissions) timings_.readback = done - first_dispatch_;
}

void CollisionDetector::run_batch(std::span<const glm::vec3> positions,
                                  std::span<const std::uint32_t> indices) {
  // A list holding a non-finite position: the CPU reference when asked for, else left stale.
  std::size_t kept = 0;
  for (const std::size_t i : batch_) {
    List& list = lists_[i];
    list.queued = false;
    if (list.finite) {
      batch_[kept++] = i;
    } else if (list.requested) {
      cpu_.detect(positions, indices, list.triangles, list.pairs);
      list.computed = true;
      list.source = positions.data();
      ++stats_.cpu_lists;
    }
  }
  batch_.resize(kept);
  if (!batch_.empty()) submit(positions);
}

void CollisionDetector::allocate(int binding, std::size_t bytes, const void* data) {
  gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, buffers_->ids[binding]);
  gl_.BufferData(GL_SHADER_STORAGE_BUFFER, static_cast<GLsizeiptr>(bytes), data, GL_DYNAMIC_DRAW);
  buffers_->bytes[binding] = bytes;
}

void CollisionDetector::submit(std::span<const glm::vec3> positions) {
  Buffers& b = *buffers_;
  // The posed positions, once (3 tightly packed floats per vertex, as the shaders read them).
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  if (positions.size_bytes() > b.bytes[kPositionsBinding])
    allocate(kPositionsBinding, positions.size_bytes(), nullptr);
  gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b.ids[kPositionsBinding]);
  gl_.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(positions.size_bytes()),
                    positions.data());
  batch_table_.clear();
  std::uint32_t active = 0;
  for (const std::size_t i : batch_) {
    const List& list = lists_[i];
    batch_table_.emplace_back(static_cast<std::uint32_t>(list.first_slot),
                              static_cast<std::uint32_t>(i), active,
                              std::bit_cast<std::uint32_t>(list.inverse_cell));
    active += static_cast<std::uint32_t>(list.triangles.size());
  }
  const std::size_t table_bytes = batch_table_.size() * sizeof(glm::uvec4);
  if (table_bytes > b.bytes[kBatchBinding]) allocate(kBatchBinding, kMostLists * 16, nullptr);
  gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b.ids[kBatchBinding]);
  gl_.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, static_cast<GLsizeiptr>(table_bytes),
                    batch_table_.data());
  stats_.submissions = 1;
  stats_.lists = static_cast<int>(batch_.size());
  stats_.slots = active;

  // About one bucket per (triangle, cell) entry of this submission: 4 per triangle.
  const std::size_t buckets = std::clamp<std::size_t>(
      std::bit_ceil(4 * std::size_t{active}), kBucketsPerInvocation * kCollisionGroupSize,
      b.buckets);
  const std::uint32_t zeros[kOutputHeaderWords] = {};
  std::size_t window = 0;
  std::uint32_t found = 0;
  for (bool first = true;; first = false) {
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b.ids[kOutputBinding]);
    gl_.BufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof zeros, zeros);
    for (int binding = 0; binding < kBufferCount; ++binding)
      gl_.BindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(binding), b.ids[binding]);
    gl_.BindBuffer(GL_DISPATCH_INDIRECT_BUFFER, b.ids[kOutputBinding]);
    const std::uint32_t values[6] = {active,
                                     static_cast<std::uint32_t>(batch_.size()),
                                     static_cast<std::uint32_t>(buckets - 1),
                                     static_cast<std::uint32_t>(b.entries),
                                     static_cast<std::uint32_t>(b.candidates),
                                     static_cast<std::uint32_t>(b.outputs)};
    auto use = [&](std::size_t pass) {
      passes_[pass]->use();
      for (int u = 0; u < 6; ++u) gl_.Uniform1ui(b.uniforms[pass][u], values[u]);
    };
    const Clock::time_point dispatched = Clock::now();
    if (first) first_dispatch_ = dispatched;
    use(0);
    gl_.DispatchCompute(std::min(65535u, (active + kCollisionGroupSize - 1) / kCollisionGroupSize),
                        1, 1);
    gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    use(1);
    gl_.DispatchCompute(
        static_cast<GLuint>(buckets / (kBucketsPerInvocation * kCollisionGroupSize)), 1, 1);
    gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    use(2);
    gl_.DispatchComputeIndirect(4 * sizeof(std::uint32_t));
    gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    use(3);
    gl_.DispatchComputeIndirect(4 * sizeof(std::uint32_t));
    gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    use(4);
    gl_.DispatchCompute(1, 1, 1);
    gl_.MemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    use(5);
    gl_.DispatchComputeIndirect(8 * sizeof(std::uint32_t));
    gl_.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    gl_.Finish();
    timings_.dispatch += Clock::now() - dispatched;
    // The counters and the first pairs in one read; the rest only when more were found.
    window = std::min(readback_window_, b.outputs);
    readback_.resize(kOutputHeaderWords + 2 * window);
    gl_.BindBuffer(GL_SHADER_STORAGE_BUFFER, b.ids[kOutputBinding]);
    gl_.GetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0,
                         static_cast<GLsizeiptr>(readback_.size() * sizeof(std::uint32_t)),
                         readback_.data());
    throw_on_gl_error(gl_, "collision passes");
    const std::size_t entries = readback_[0], candidates = readback_[1];
    found = readback_[2];
    // A buffer too small: grow it and run again (capacities stay for later calls).
    if (entries > b.entries) {
      b.entries = 2 * entries;
      allocate(kEntriesBinding, b.entries * sizeof(glm::uvec4), nullptr);
      allocate(kSortedBinding, b.entries * sizeof(glm::uvec4), nullptr);
    } else if (candidates > b.candidates) {
      b.candidates = 2 * candidates;
      allocate(kCandidatesBinding, b.candidates * sizeof(glm::uvec2), nullptr);
    } else if (found > b.outputs) {
      b.outputs = 2 * static_cast<std::size_t>(found);
      allocate(kOutputBinding, kOutputHeaderWords * 4 + b.outputs * sizeof(glm::uvec2), nullptr);
    } else {
      stats_.entries = entries;
      stats_.candidates = candidates;
      break;
    }
    throw_on_gl_error(gl_, "collision buffers");
  }
  if (found > window) {
    readback_.resize(kOutputHeaderWords + 2 * static_cast<std::size_t>(found));
    gl_.GetBufferSubData(
        GL_SHADER_STORAGE_BUFFER,
        static_cast<GLintptr>((kOutputHeaderWords + 2 * window) * sizeof(std::uint32_t)),
        static_cast<GLsizeiptr>(2 * (found - window) * sizeof(std::uint32_t)),
        readback_.data() + kOutputHeaderWords + 2 * window);
    throw_on_gl_error(gl_, "collision readback");
  }
  readback_window_ = std::max<std::size_t>(1024, 2 * static_cast<std::size_t>(found));

  for (const std::size_t i : batch_) lists_[i].pairs.clear();
  const glm::vec3* p = positions.data();
  for (std::uint32_t k = 0; k < found; ++k) {
    std::uint32_t a = readback_[kOutputHeaderWords + 2 * k];
    const std::uint32_t b_slot = readback_[kOutputHeaderWords + 2 * k + 1];
    const bool undecided = (a & kUndecidedBit) != 0;
    a &= ~kUndecidedBit;
    List& list = lists_[slot_list_[a]];
    const std::size_t s = a - list.first_slot, t = b_slot - list.first_slot;
    if (undecided) {  // the CPU's exact test, smaller triangle id first as the reference has it
      ++stats_.undecided;
      const std::uint32_t* c = list.corners.data();
      const glm::vec3 ta[3] = {p[c[3 * s]], p[c[3 * s + 1]], p[c[3 * s + 2]]};
      const glm::vec3 tb[3] = {p[c[3 * t]], p[c[3 * t + 1]], p[c[3 * t + 2]]};
      if (!deform::triangles_intersect(ta, tb)) continue;
    }
    const std::uint32_t first = list.triangles[s], second = list.triangles[t];
    list.pairs.push_back({std::min(first, second), std::max(first, second)});
  }
  for (const std::size_t i : batch_) {
    List& list = lists_[i];
    std::sort(list.pairs.begin(), list.pairs.end());
    list.pairs.erase(std::unique(list.pairs.begin(), list.pairs.end()), list.pairs.end());
    list.computed = true;
    list.source = positions.data();
  }
}

}  // namespace sweepd::gpu
