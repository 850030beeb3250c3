#include "protocol/buffer_budget.h"

namespace sweepd::protocol {

bool BufferBudget::take(std::size_t bytes) {
  std::size_t used = used_.load();
  do {
    if (bytes > limit_ || used > limit_ - bytes) return false;
  } while (!used_.compare_exchange_weak(used, used + bytes));
  return true;
}

}  // namespace sweepd::protocol
