// libFuzzer target: fuzz_websocket (fuzz/fuzz_inputs.h), the frames as a --ws-listen connection's
// bytes. Built by the fuzz preset; `make fuzz` runs it.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_inputs.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  sweepd::fuzz::prepare();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  sweepd::fuzz::fuzz_websocket({data, size});  // accepted or refused: both are fine
  return 0;
}
