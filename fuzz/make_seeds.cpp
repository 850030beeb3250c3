// make_seeds DIR: writes fuzz/seed_inputs.h's seeds as DIR/<target>/seed_<n>, the starting
// corpus of each libFuzzer target (fuzz/run_fuzzers.sh calls it).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "fuzz/seed_inputs.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_seeds DIR\n");
    return 2;
  }
  for (const auto& [target, inputs] : sweepd::fuzz::seed_inputs()) {
    const std::filesystem::path folder = std::filesystem::path(argv[1]) / target;
    std::filesystem::create_directories(folder);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      std::ofstream(folder / ("seed_" + std::to_string(i)), std::ios::binary)
          .write(reinterpret_cast<const char*>(inputs[i].data()),
                 static_cast<std::streamsize>(inputs[i].size()));
    }
    std::printf("%s: %zu seeds\n", target.c_str(), inputs.size());
  }
  return 0;
}
