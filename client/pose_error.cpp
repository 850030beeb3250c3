#include "client/pose_error.h"

namespace sweepd::client {

std::string pose_error_cause(const protocol::Error& error) {
  std::string message = error.message() ? error.message()->str() : "";
  const std::string own = "pose " + std::to_string(error.sequence()) + ": ";
  if (error.sequence() != 0 && message.compare(0, own.size(), own) == 0)
    message.erase(0, own.size());
  return std::string("server error ") + protocol::EnumNameErrorCode(error.code()) + ": " + message;
}

}  // namespace sweepd::client
