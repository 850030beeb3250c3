// Vertex blocks: splits a per-vertex job into contiguous blocks run on several threads.
//
//   vertex_count  vertices (or items) of the job
//   threads       threads to use (values < 1 mean 1; never more than one per granule)
//   job           called as job(begin, end) once per block; blocks cover [0, vertex_count)
//                 without overlap. The caller's thread runs the last block.
//   granule       every block but the last starts and ends at a multiple of it (a loop that
//                 handles 8 items at once is never handed part of its 8)
// Each vertex is computed by the same code whatever block it falls in, so a job whose vertices
// are independent gives bit-identical results for every thread count. Starting the threads is
// the only allocation; it happens per call.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace sweepd::deform {

template <class Job>
void run_in_vertex_blocks(std::size_t vertex_count, int threads, const Job& job,
                          std::size_t granule = 1) {
  const std::size_t granules = (vertex_count + granule - 1) / granule;
  const std::size_t blocks = std::clamp<std::size_t>(
      threads < 1 ? 1 : static_cast<std::size_t>(threads), 1, std::max<std::size_t>(granules, 1));
  if (blocks == 1) {
    job(std::size_t{0}, vertex_count);
    return;
  }
  std::vector<std::jthread> workers;
  workers.reserve(blocks - 1);
  const auto block_begin = [&](std::size_t b) { return granules * b / blocks * granule; };
  for (std::size_t b = 0; b + 1 < blocks; ++b)
    workers.emplace_back(
        [&job, begin = block_begin(b), end = block_begin(b + 1)] { job(begin, end); });
  job(block_begin(blocks - 1), vertex_count);
}  // the jthreads join here

}  // namespace sweepd::deform
