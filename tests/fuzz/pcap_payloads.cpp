// strata_fuzz_pcap_payloads CAPTURE PORT COUNT DIRECTORY: writes COUNT UDP payloads sent to PORT, spread
// evenly over the capture, as files DIRECTORY/<capture name>-<index>. Seeds for the packet decoders' fuzz
// targets made at build time from the third-party captures, which stay out of the repository.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

#include "drivers/lidar/pcap_reader.hpp"

namespace {

std::size_t count_datagrams(const std::filesystem::path& capture, std::uint16_t port) {
  strata::lidar::PcapReader reader(capture);
  std::size_t count = 0;
  while (const auto datagram = reader.next())
    count += datagram->destination_port == port ? 1 : 0;
  return count;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s CAPTURE PORT COUNT DIRECTORY\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path capture = argv[1];
    const auto port = static_cast<std::uint16_t>(std::stoul(argv[2]));
    const std::size_t wanted = std::stoul(argv[3]);
    const std::filesystem::path directory = argv[4];
    std::filesystem::create_directories(directory);
    const std::size_t available = count_datagrams(capture, port);
    const std::size_t step = wanted == 0 ? 1 : std::max<std::size_t>(1, available / wanted);
    strata::lidar::PcapReader reader(capture);
    std::size_t index = 0;
    std::size_t written = 0;
    while (const auto datagram = reader.next()) {
      if (datagram->destination_port != port)
        continue;
      if (index++ % step != 0 || written == wanted)
        continue;
      const auto name = capture.stem().string() + "-" + std::to_string(written++);
      std::ofstream out(directory / name, std::ios::binary);
      out.write(reinterpret_cast<const char*>(datagram->payload.data()),
                static_cast<std::streamsize>(datagram->payload.size()));
    }
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "%s: %s\n", argv[0], error.what());
    return 1;
  }
}
