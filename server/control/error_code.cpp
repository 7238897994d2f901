#include "server/control/error_code.hpp"

namespace strata {

std::string_view to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::kBadJson:
      return "bad_json";
    case ErrorCode::kBadMessage:
      return "bad_message";
    case ErrorCode::kUnknownOp:
      return "unknown_op";
    case ErrorCode::kNotFound:
      return "not_found";
    case ErrorCode::kMethodNotAllowed:
      return "method_not_allowed";
    case ErrorCode::kBadRequest:
      return "bad_request";
    case ErrorCode::kUnavailable:
      return "unavailable";
    case ErrorCode::kBadParams:
      return "bad_params";
    case ErrorCode::kUnauthorized:
      return "unauthorized";
    case ErrorCode::kRateLimited:
      return "rate_limited";
    case ErrorCode::kForbidden:
      return "forbidden";
    case ErrorCode::kCorruptFile:
      return "corrupt_file";
    case ErrorCode::kIoError:
      return "io_error";
    case ErrorCode::kStaleCommand:
      return "stale_command";
    case ErrorCode::kInternal:
      return "internal";
  }
  return "internal";
}

}  // namespace strata
