// Lidar packet decoding speed: each shared capture decoded in memory, over and over, on one thread.
// Rates are per second of the thread's CPU time (one core; decode_wall_x_real_time: per wall-clock
// second, lower when other processes share the core). Prints JSON: packets/s and points/s for the
// decoder alone and for the whole chain (decoder + revolution assembly + ScanEvents), and the ratio to the
// sensor's real-time packet rate (from the capture's own timestamps, and the datasheet's). Target: >= 10x
// real time.
#include <time.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "drivers/lidar/lidar_scan_builder.hpp"
#include "drivers/lidar/pcap_reader.hpp"

namespace {

using strata::lidar::LidarModel;
using strata::lidar::LidarSetup;

struct Packet {
  double stamp;
  std::vector<std::uint8_t> payload;
};

struct Capture {
  std::string file;
  LidarSetup setup;
};

/// This thread's CPU time: rates per core, unaffected by other processes sharing the machine.
double thread_seconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9;
}

}  // namespace

int main(int argc, char** argv) {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  const std::filesystem::path dir =
      (from_env != nullptr ? std::filesystem::path(from_env) : std::filesystem::path(STRATA_DATA_DIR)) /
      "lidar_pcap";
  const double min_seconds = argc > 1 ? std::stod(argv[1]) : 1.0;
  const std::vector<Capture> captures = {
      {"hdl32_example.pcap", {LidarModel::kHdl32e, dir / "32db.yaml"}},
      {"velodyne_example.pcap", {LidarModel::kVlp16, dir / "VLP16db.yaml"}},
      {"velodyne_vlp16.pcap", {LidarModel::kVlp16, dir / "VLP16db.yaml"}},
      {"ouster_example.pcap", {LidarModel::kOs1, dir / "ouster_example.json"}},
  };
  std::printf("[\n");
  bool first = true;
  for (const Capture& capture : captures) {
    const std::filesystem::path file = dir / capture.file;
    if (!std::filesystem::exists(file)) {
      std::fprintf(stderr, "lidar_decode_bench: %s not found (set STRATA_DATA_DIR)\n", file.c_str());
      continue;
    }
    std::vector<Packet> packets;
    strata::lidar::PcapReader reader(file);
    const std::uint16_t port = strata::lidar::default_data_port(capture.setup.model);
    while (const auto datagram = reader.next())
      if (datagram->destination_port == port)
        packets.push_back({datagram->stamp, {datagram->payload.begin(), datagram->payload.end()}});
    if (packets.size() < 2)
      continue;
    const double captured_rate =
        static_cast<double>(packets.size() - 1) / (packets.back().stamp - packets.front().stamp);
    const double nominal_rate = strata::lidar::nominal_packet_rate(capture.setup.model);

    // Decoder alone.
    auto decoder = strata::lidar::make_decoder(capture.setup);
    strata::lidar::DecodedPacket out;
    std::size_t decoded = 0;
    std::size_t points = 0;
    double start = thread_seconds();
    const auto wall_start = std::chrono::steady_clock::now();
    do {
      for (const Packet& packet : packets) {
        out.clear();
        std::visit([&](auto& d) { d.decode(packet.payload, packet.stamp, out); }, decoder);
        points += out.points.size();
        ++decoded;
      }
    } while ((thread_seconds() - start) < min_seconds);
    const double decode_seconds = (thread_seconds() - start);
    const double decode_wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    // The whole chain to ScanEvents.
    std::size_t chained = 0;
    std::size_t scans = 0;
    // The capture loops: its azimuths wrap on as a sensor's would (the repeated stamps do not matter).
    strata::lidar::LidarScanBuilder builder(capture.setup);
    std::vector<strata::ScanEvent> built;
    start = thread_seconds();
    do {
      for (const Packet& packet : packets) {
        builder.add_payload(packet.payload, packet.stamp, built);
        ++chained;
      }
      scans += built.size();
      built.clear();
    } while ((thread_seconds() - start) < min_seconds);
    const double chain_seconds = (thread_seconds() - start);

    const double decode_rate = static_cast<double>(decoded) / decode_seconds;
    const double chain_rate = static_cast<double>(chained) / chain_seconds;
    std::printf(
        "%s  {\"capture\": \"%s\", \"sensor\": \"%s\", \"packets\": %zu, \"captured_packets_per_s\": %.0f, "
        "\"nominal_packets_per_s\": %.0f,\n   \"decode_packets_per_s\": %.0f, \"decode_points_per_s\": %.0f, "
        "\"decode_x_real_time\": %.1f, \"decode_wall_x_real_time\": %.1f,\n   \"chain_packets_per_s\": %.0f, "
        "\"chain_scans\": %zu, "
        "\"chain_x_real_time\": %.1f}",
        first ? "" : ",\n", capture.file.c_str(), strata::lidar::sensor_name(capture.setup.model).c_str(),
        packets.size(), captured_rate, nominal_rate, decode_rate,
        static_cast<double>(points) / decode_seconds, decode_rate / std::max(captured_rate, nominal_rate),
        static_cast<double>(decoded) / decode_wall_seconds / std::max(captured_rate, nominal_rate),
        chain_rate, scans, chain_rate / std::max(captured_rate, nominal_rate));
    first = false;
  }
  std::printf("\n]\n");
  return 0;
}
