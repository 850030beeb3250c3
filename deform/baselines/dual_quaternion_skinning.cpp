#include "deform/baselines/dual_quaternion_skinning.h"

#include <array>
#include <cassert>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include "deform/baselines/skinning_buffers.h"
#include "deform/baselines/skinning_items.h"
#include "deform/simd/vertex_blocks.h"

namespace sweepd::deform {

namespace {

// A joint's dual quaternion as two lane sets, (x, y, z, w) each: 8 consecutive floats.
struct JointDualQuaternion {
  FloatLanes real, dual;
};

// Converts every skinning matrix into the calling thread's buffer.
std::span<const JointDualQuaternion> joint_dual_quaternions(std::span<const glm::mat4> skinning) {
  thread_local std::vector<JointDualQuaternion> buffer;
  if (buffer.size() < skinning.size()) buffer.resize(skinning.size());
  for (std::size_t j = 0; j < skinning.size(); ++j) {
    const DualQuaternion q = to_dual_quaternion(skinning[j]);
    buffer[j] = {FloatLanes{q.real.x, q.real.y, q.real.z, q.real.w},
                 FloatLanes{q.dual.x, q.dual.y, q.dual.z, q.dual.w}};
  }
  return std::span<const JointDualQuaternion>(buffer.data(), skinning.size());
}

// Items [0, count) with kJoints influences each: the blend, then the rigid transform of the unit
// result. Inlined into each instruction set's loop.
template <int kJoints, bool kNormals>
[[gnu::always_inline]] inline void skin_items(SkinningItems d, std::size_t count,
                                              const JointDualQuaternion* joint_dq,
                                              glm::vec3* positions, glm::vec3* normals) {
  for (std::size_t i = 0; i < count; ++i) {
    if constexpr (kJoints == 0) {
      store_rest(d, i, positions, normals, kNormals);
    } else {
      const JointDualQuaternion& first = joint_dq[*d.joint];
      FloatLanes real = first.real * *d.weight, dual = first.dual * *d.weight;
      ++d.joint;
      ++d.weight;
      for (int k = 1; k < kJoints; ++k, ++d.joint, ++d.weight) {
        const JointDualQuaternion& q = joint_dq[*d.joint];
        const float signed_weight =
            sum_of_lanes(q.real * first.real) < 0.0f ? -*d.weight : *d.weight;
        real += q.real * signed_weight;
        dual += q.dual * signed_weight;
      }
      const float inverse_length = 1.0f / std::sqrt(sum_of_lanes(real * real));
      // Rotation by the unit real part, translation 2 * (dual * conj(real)).xyz (Kavan et al.).
      const glm::vec3 r = glm::vec3(real[0], real[1], real[2]) * inverse_length;
      const glm::vec3 e = glm::vec3(dual[0], dual[1], dual[2]) * inverse_length;
      const float rw = real[3] * inverse_length, ew = dual[3] * inverse_length;
      const glm::vec3 translation = 2.0f * (rw * e - ew * r + glm::cross(r, e));
      const glm::vec3 p(d.position[i]);
      positions[d.vertex[i]] = p + 2.0f * glm::cross(r, glm::cross(r, p) + rw * p) + translation;
      if constexpr (kNormals) {
        const glm::vec3 n(d.normal[i]);
        // A unit quaternion turns the unit rest normal into a unit normal: no renormalisation.
        normals[d.vertex[i]] = n + 2.0f * glm::cross(r, glm::cross(r, n) + rw * n);
      }
    }
  }
}

template <int kJoints, bool kNormals>
void skin_items_baseline(SkinningItems d, std::size_t count, const JointDualQuaternion* joint_dq,
                         glm::vec3* positions, glm::vec3* normals) {
  skin_items<kJoints, kNormals>(d, count, joint_dq, positions, normals);
}

#if defined(__x86_64__)
// AVX2 + FMA: kSkinningChunk (8) items at once, one per lane, each quantity a register of 8
// (structure of arrays): each influence's 8 joint dual quaternions are loaded as rows and
// transposed, so the blend, the normalisation and the transform are plain lane arithmetic.
struct Lanes3 {
  __m256 x, y, z;
};

[[gnu::target("avx2,fma")]] inline Lanes3 cross(const Lanes3& a, const Lanes3& b) {
  return {_mm256_fmsub_ps(a.y, b.z, _mm256_mul_ps(a.z, b.y)),
          _mm256_fmsub_ps(a.z, b.x, _mm256_mul_ps(a.x, b.z)),
          _mm256_fmsub_ps(a.x, b.y, _mm256_mul_ps(a.y, b.x))};
}

// v + 2 r × (r × v + rw v): v turned by the unit quaternion (r, rw).
[[gnu::target("avx2,fma")]] inline Lanes3 rotate(const Lanes3& r, __m256 rw, const Lanes3& v) {
  const __m256 two = _mm256_set1_ps(2.0f);
  const Lanes3 rv = cross(r, v);
  const Lanes3 outer = cross(r, {_mm256_fmadd_ps(rw, v.x, rv.x), _mm256_fmadd_ps(rw, v.y, rv.y),
                                 _mm256_fmadd_ps(rw, v.z, rv.z)});
  return {_mm256_fmadd_ps(two, outer.x, v.x), _mm256_fmadd_ps(two, outer.y, v.y),
          _mm256_fmadd_ps(two, outer.z, v.z)};
}

// Rows r[0..7] of 8 floats become columns: r[c] holds component c of every row.
[[gnu::target("avx2,fma")]] inline void transpose8(__m256 r[8]) {
  const __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
  const __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
  const __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
  const __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
  const __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xEE);
  const __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xEE);
  const __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xEE);
  const __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xEE);
  r[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
  r[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
  r[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
  r[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
  r[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
  r[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
  r[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
  r[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
}

// x, y, z of 8 consecutive vec4s (the table's rest positions or normals).
[[gnu::target("avx2,fma")]] inline Lanes3 load_points(const glm::vec4* points) {
  __m256 r[8];
  for (int i = 0; i < 8; ++i) r[i] = _mm256_castps128_ps256(_mm_loadu_ps(&points[i].x));
  // Only the low halves hold data; transposing 8 rows of 4 gives x, y, z, w in r[0..3].
  transpose8(r);
  return {r[0], r[1], r[2]};
}

[[gnu::target("avx2,fma")]] inline void store_points(const Lanes3& p, const std::uint32_t* vertex,
                                                     glm::vec3* out) {
  alignas(32) float x[8], y[8], z[8];
  _mm256_store_ps(x, p.x);
  _mm256_store_ps(y, p.y);
  _mm256_store_ps(z, p.z);
  for (int i = 0; i < 8; ++i) out[vertex[i]] = glm::vec3(x[i], y[i], z[i]);
}

template <int kJoints, bool kNormals>
[[gnu::target("avx2,fma")]] void skin_items_avx2(SkinningItems d, std::size_t count,
                                                 const JointDualQuaternion* joint_dq,
                                                 glm::vec3* positions, glm::vec3* normals) {
  if constexpr (kJoints == 0) {
    skin_items<0, kNormals>(d, count, joint_dq, positions, normals);
  } else {
    const __m256 sign_bit = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps();
    for (std::size_t chunk = 0; chunk < count; chunk += 8) {
      __m256 blend[8], first_real[4];
      for (int k = 0; k < kJoints; ++k) {
        __m256 q[8];
        alignas(32) float weight[8];
        for (int i = 0; i < 8; ++i) {
          q[i] =
              _mm256_loadu_ps(reinterpret_cast<const float*>(&joint_dq[d.joint[i * kJoints + k]]));
          weight[i] = d.weight[i * kJoints + k];
        }
        transpose8(q);
        __m256 w = _mm256_load_ps(weight);
        if (k == 0) {
          for (int c = 0; c < 4; ++c) first_real[c] = q[c];
          for (int c = 0; c < 8; ++c) blend[c] = _mm256_mul_ps(q[c], w);
          continue;
        }
        __m256 dot = _mm256_mul_ps(q[0], first_real[0]);
        for (int c = 1; c < 4; ++c) dot = _mm256_fmadd_ps(q[c], first_real[c], dot);
        // The quaternion pointing away from the first is blended with its sign flipped.
        w = _mm256_xor_ps(w, _mm256_and_ps(_mm256_cmp_ps(dot, zero, _CMP_LT_OQ), sign_bit));
        for (int c = 0; c < 8; ++c) blend[c] = _mm256_fmadd_ps(q[c], w, blend[c]);
      }
      __m256 length2 = _mm256_mul_ps(blend[0], blend[0]);
      for (int c = 1; c < 4; ++c) length2 = _mm256_fmadd_ps(blend[c], blend[c], length2);
      const __m256 inverse = _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(length2));
      const Lanes3 r{_mm256_mul_ps(blend[0], inverse), _mm256_mul_ps(blend[1], inverse),
                     _mm256_mul_ps(blend[2], inverse)};
      const Lanes3 e{_mm256_mul_ps(blend[4], inverse), _mm256_mul_ps(blend[5], inverse),
                     _mm256_mul_ps(blend[6], inverse)};
      const __m256 rw = _mm256_mul_ps(blend[3], inverse), ew = _mm256_mul_ps(blend[7], inverse);
      const __m256 two = _mm256_set1_ps(2.0f);
      // Rotation by the unit real part, translation 2 * (dual * conj(real)).xyz (Kavan et al.).
      const Lanes3 re = cross(r, e);
      const Lanes3 translation{
          _mm256_mul_ps(two, _mm256_add_ps(_mm256_fmsub_ps(rw, e.x, _mm256_mul_ps(ew, r.x)), re.x)),
          _mm256_mul_ps(two, _mm256_add_ps(_mm256_fmsub_ps(rw, e.y, _mm256_mul_ps(ew, r.y)), re.y)),
          _mm256_mul_ps(two,
                        _mm256_add_ps(_mm256_fmsub_ps(rw, e.z, _mm256_mul_ps(ew, r.z)), re.z))};
      const Lanes3 turned = rotate(r, rw, load_points(d.position + chunk));
      store_points({_mm256_add_ps(turned.x, translation.x), _mm256_add_ps(turned.y, translation.y),
                    _mm256_add_ps(turned.z, translation.z)},
                   d.vertex + chunk, positions);
      if constexpr (kNormals)
        store_points(rotate(r, rw, load_points(d.normal + chunk)), d.vertex + chunk, normals);
      d.joint += 8 * kJoints;
      d.weight += 8 * kJoints;
    }
  }
}
#endif

// The loops, for skinning_loops.
struct DualQuaternionLoops {
  using Loop = void (*)(SkinningItems, std::size_t, const JointDualQuaternion*, glm::vec3*,
                        glm::vec3*);
  template <int kJoints, bool kNormals>
  static constexpr Loop baseline = &skin_items_baseline<kJoints, kNormals>;
#if defined(__x86_64__)
  template <int kJoints, bool kNormals>
  static constexpr Loop avx2 = &skin_items_avx2<kJoints, kNormals>;
#endif
};

}  // namespace

DualQuaternion to_dual_quaternion(const glm::mat4& rigid) {
  const glm::mat3 rotation(glm::normalize(glm::vec3(rigid[0])), glm::normalize(glm::vec3(rigid[1])),
                           glm::normalize(glm::vec3(rigid[2])));
  DualQuaternion q;
  q.real = glm::normalize(glm::quat_cast(rotation));
  const glm::vec3 t(rigid[3]);
  q.dual = glm::quat(0.0f, t.x, t.y, t.z) * q.real * 0.5f;
  return q;
}

void dual_quaternion_skinning(const SkinningTable& table, std::span<const glm::mat4> skinning,
                              std::span<glm::vec3> positions, std::span<glm::vec3> normals,
                              int threads) {
  assert(skinning_buffers_fit(table, skinning.size(), positions.size(), normals.size()));
  const std::span<const JointDualQuaternion> joint_dq = joint_dual_quaternions(skinning);
  const auto& loops = skinning_loops<DualQuaternionLoops>(table.instructions());
  run_in_vertex_blocks(
      table.item_count(), threads,
      [&](std::size_t begin, std::size_t end) {
        for_each_group_in(table, begin, end,
                          [&](int influences, const SkinningItems& items, std::size_t count) {
                            loops[influences * 2 + (normals.empty() ? 0 : 1)](
                                items, count, joint_dq.data(), positions.data(), normals.data());
                          });
      },
      kSkinningChunk);
}

void dual_quaternion_skinning(const Model& model, std::span<const glm::mat4> skinning,
                              std::span<glm::vec3> positions, std::span<glm::vec3> normals) {
  dual_quaternion_skinning(SkinningTable(model), skinning, positions, normals);
}

}  // namespace sweepd::deform
