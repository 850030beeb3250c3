#include "server/handlers/request_error.h"

#include <stdexcept>

#include "server/services/position_map_service.h"

namespace sweepd::server {

protocol::ErrorCode error_code_of(const std::exception& error) {
  if (dynamic_cast<const PositionMapUnavailable*>(&error) != nullptr)
    return protocol::ErrorCode::NotAvailable;
  if (dynamic_cast<const std::invalid_argument*>(&error) != nullptr)
    return protocol::ErrorCode::InvalidArgument;
  return protocol::ErrorCode::Internal;
}

}  // namespace sweepd::server
