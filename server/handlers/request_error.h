// RequestError: why a request is answered with an Error instead of its reply — the code and
// message the Error carries, the pose sequence it names (0: none), and the model whose error
// count (Stats) it adds to (0: none). What request handlers return when they refuse.
// error_code_of: the code for what work on a worker threw — NotAvailable without a GPU for it
// (PositionMapUnavailable), InvalidArgument for a request the work refused
// (std::invalid_argument), else Internal.
#pragma once

#include <cstdint>
#include <exception>
#include <string>

#include "protocol/sweepd_generated.h"

namespace sweepd::server {

struct RequestError {
  protocol::ErrorCode code = protocol::ErrorCode::Internal;
  std::string message;
  std::uint64_t sequence = 0;
  std::uint32_t charged_model = 0;
};

protocol::ErrorCode error_code_of(const std::exception& error);

}  // namespace sweepd::server
