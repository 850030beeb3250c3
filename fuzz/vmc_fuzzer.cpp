// libFuzzer target: fuzz_vmc (fuzz/fuzz_inputs.h). Built by the fuzz preset; `make fuzz` runs it.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_inputs.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  sweepd::fuzz::prepare();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sweepd::fuzz::fuzz_vmc({data, size});  // accepted or refused: both are fine
  return 0;
}
