#include "deform/mesh/length_weighted_smoothing.h"

namespace sweepd::deform {

void LengthWeightedSmoothing::smooth(int columns, int passes, std::vector<float>& table) const {
  std::vector<float> next = table;
  for (int pass = 0; pass < passes; ++pass) {
    for (std::size_t i = 0; i < rows_.size(); ++i) {
      const std::size_t row = rows_[i];
      float* out = &next[row * columns];
      for (int c = 0; c < columns; ++c) out[c] = 0.5f * table[row * columns + c];
      for (std::uint32_t n = first_[i]; n < first_[i + 1]; ++n)
        for (int c = 0; c < columns; ++c)
          out[c] += neighbours_[n].weight * table[neighbours_[n].row * columns + c];
    }
    table.swap(next);
  }
}

}  // namespace sweepd::deform
