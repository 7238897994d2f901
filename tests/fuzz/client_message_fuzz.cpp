// WebSocket control messages (text frames from any client): parse and validate.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "server/protocol/client_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const strata::protocol::ParsedClientMessage parsed = strata::protocol::parse_client_message(text);
  if (parsed.request) {
    static_cast<void>(strata::protocol::needs_operator(*parsed.request));
    if (const auto* save = std::get_if<strata::protocol::SaveMapRequest>(&*parsed.request);
        save != nullptr && !strata::protocol::is_valid_map_name(save->name))
      __builtin_trap();  // an accepted save must carry a valid file name
    if (const auto* load = std::get_if<strata::protocol::LoadMapRequest>(&*parsed.request);
        load != nullptr && !strata::protocol::is_valid_map_name(load->name))
      __builtin_trap();
  } else if (parsed.error_message.empty()) {
    __builtin_trap();  // a refusal always says why
  }
  return 0;
}
