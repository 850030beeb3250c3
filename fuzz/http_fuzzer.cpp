// libFuzzer target: fuzz_http (fuzz/fuzz_inputs.h, fuzz/fuzz_http.cpp), the HTTP side port's
// request heads. Built by the fuzz preset; `make fuzz` runs it.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_inputs.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sweepd::fuzz::fuzz_http({data, size});  // accepted or refused: both are fine
  return 0;
}
