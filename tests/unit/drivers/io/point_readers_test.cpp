#include <gtest/gtest.h>
#include <lzf.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "drivers/io/pcd_reader.hpp"
#include "drivers/io/pcd_writer.hpp"
#include "drivers/io/ply_reader.hpp"
#include "drivers/io/point_cloud_file.hpp"
#include "drivers/io/point_file_error.hpp"
#include "drivers/io/threedtk_reader.hpp"
#include "drivers/io/xyz_reader.hpp"

namespace strata::io {
namespace {

namespace fs = std::filesystem;

class PointReaders : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("strata_readers_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& bytes) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  template <typename T>
  static std::string bytes_of(T value, bool big_endian = false) {
    std::string out(sizeof value, '\0');
    std::memcpy(out.data(), &value, sizeof value);
    if (big_endian)
      std::reverse(out.begin(), out.end());
    return out;
  }

  /// The error message of reading `path`, which must throw PointFileError.
  template <typename Reader>
  static std::string error_of(Reader reader, const fs::path& path) {
    try {
      static_cast<void>(reader(path));
    } catch (const PointFileError& error) {
      EXPECT_NE(std::string(error.what()).find(path.filename().string()), std::string::npos)
          << "the message names the file: " << error.what();
      return error.what();
    }
    ADD_FAILURE() << "no PointFileError for " << path;
    return {};
  }
  /// The cloud readers also take a stream (for the fuzzers): this picks their path overload.
  static std::string error_of(LoadedCloud (*reader)(const fs::path&), const fs::path& path) {
    return error_of<LoadedCloud (*)(const fs::path&)>(reader, path);
  }

  fs::path dir_;
};

const std::string kPcdHeader =
    "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z intensity\nSIZE 4 4 4 1\n"
    "TYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 3\n";

TEST_F(PointReaders, PcdAsciiDropsNaN) {
  const LoadedCloud cloud =
      read_pcd(write("a.pcd", kPcdHeader + "DATA ascii\n1 2 3 7\nnan nan nan 0\n-4.5 5 6e-1 9\n"));
  ASSERT_EQ(cloud.points.size(), 2U);
  EXPECT_EQ(cloud.dropped_non_finite, 1U);
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(-4.5, 5, 0.6));
}

TEST_F(PointReaders, PcdBinary) {
  std::string data;
  for (const float v : {1.f, 2.f, 3.f})
    data += bytes_of(v);
  data += '\x07';
  for (const float v : {std::numeric_limits<float>::infinity(), 0.f, 0.f})
    data += bytes_of(v);
  data += '\x00';
  for (const float v : {4.f, 5.f, 6.f})
    data += bytes_of(v);
  data += '\x09';
  const LoadedCloud cloud = read_pcd(write("b.pcd", kPcdHeader + "DATA binary\n" + data));
  ASSERT_EQ(cloud.points.size(), 2U);
  EXPECT_EQ(cloud.dropped_non_finite, 1U);
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(4, 5, 6));
}

TEST_F(PointReaders, PcdBinaryCompressed) {
  // Fields one after another: all x, all y, all z, all intensity; then LZF.
  std::string soa;
  for (const float v : {1.f, 4.f, 7.f})
    soa += bytes_of(v);
  for (const float v : {2.f, 5.f, 8.f})
    soa += bytes_of(v);
  for (const float v : {3.f, 6.f, 9.f})
    soa += bytes_of(v);
  soa += std::string("\x01\x02\x03", 3);
  std::vector<char> packed(soa.size() + 64);
  const unsigned packed_size = lzf_compress(soa.data(), static_cast<unsigned>(soa.size()), packed.data(),
                                            static_cast<unsigned>(packed.size()));
  ASSERT_GT(packed_size, 0U);
  const std::string data = bytes_of(std::uint32_t{packed_size}) +
                           bytes_of(static_cast<std::uint32_t>(soa.size())) +
                           std::string(packed.data(), packed_size);
  const LoadedCloud cloud = read_pcd(write("c.pcd", kPcdHeader + "DATA binary_compressed\n" + data));
  ASSERT_EQ(cloud.points.size(), 3U);
  EXPECT_EQ(cloud.points[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(cloud.points[2], Eigen::Vector3d(7, 8, 9));
  // A cut compressed block is truncated, corrupt bytes fail decompression.
  EXPECT_NE(error_of(read_pcd, write("cut.pcd", kPcdHeader + "DATA binary_compressed\n" + data.substr(0, 12)))
                .find("truncated"),
            std::string::npos);
  std::string corrupt = data;
  corrupt[8] = '\xff';
  corrupt[9] = '\xff';
  EXPECT_NE(
      error_of(read_pcd, write("bad.pcd", kPcdHeader + "DATA binary_compressed\n" + corrupt)).find("corrupt"),
      std::string::npos);
}

TEST_F(PointReaders, PcdTimesAreReadWithThePointsKept) {
  const std::string header =
      "VERSION 0.7\nFIELDS x y z time\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 3\nHEIGHT 1\n"
      "POINTS 3\n";
  const LoadedCloud ascii =
      read_pcd(write("t.pcd", header + "DATA ascii\n1 2 3 -0.09\nnan 0 0 -0.05\n4 5 6 -0.01\n"));
  ASSERT_EQ(ascii.points.size(), 2U);
  EXPECT_EQ(ascii.times, (std::vector<float>{-0.09f, -0.01f}));  // the dropped point's time with it
  EXPECT_NE(error_of(read_pcd, write("tx.pcd", header + "DATA ascii\n1 2 3 soon\n1 2 3 0\n1 2 3 0\n"))
                .find("time 'soon' is not a number"),
            std::string::npos);
  // What a recording writes, read back bit for bit; without times, no time field and none read.
  const std::vector<Eigen::Vector3f> points{{1, 2, 3}, {4, 5, 6}};
  const LoadedCloud binary = read_pcd(write("tb.pcd", encode_binary_pcd(points, {-0.1f, -1.0f / 3.0f})));
  EXPECT_EQ(binary.times, (std::vector<float>{-0.1f, -1.0f / 3.0f}));
  EXPECT_EQ(binary.points[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_TRUE(read_pcd(write("tn.pcd", encode_binary_pcd(points))).times.empty());
  // Compressed: the time field's values after all the coordinates.
  std::string soa;
  for (const float v : {1.f, 4.f, 2.f, 5.f, 3.f, 6.f, -0.2f, -0.3f})
    soa += bytes_of(v);
  std::vector<char> packed(soa.size() + 64);
  const unsigned packed_size = lzf_compress(soa.data(), static_cast<unsigned>(soa.size()), packed.data(),
                                            static_cast<unsigned>(packed.size()));
  ASSERT_GT(packed_size, 0U);
  const std::string two =
      "VERSION 0.7\nFIELDS x y z time\nSIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\n"
      "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary_compressed\n";
  const LoadedCloud compressed =
      read_pcd(write("tc.pcd", two + bytes_of(std::uint32_t{packed_size}) +
                                   bytes_of(static_cast<std::uint32_t>(soa.size())) +
                                   std::string(packed.data(), packed_size)));
  EXPECT_EQ(compressed.points[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(compressed.times, (std::vector<float>{-0.2f, -0.3f}));
}

TEST_F(PointReaders, PcdErrors) {
  EXPECT_NE(error_of(read_pcd, write("t.pcd", kPcdHeader + "DATA binary\n" + std::string(10, '\0')))
                .find("truncated"),
            std::string::npos);
  EXPECT_NE(error_of(read_pcd, write("t2.pcd", kPcdHeader + "DATA ascii\n1 2 3 4\n")).find("truncated"),
            std::string::npos);
  EXPECT_NE(error_of(read_pcd, write("h.pcd", "hello world\n")).find("not a PCD"), std::string::npos);
  EXPECT_NE(error_of(read_pcd, write("n.pcd", "VERSION 0.7\nFIELDS x y z\n")).find("DATA"),
            std::string::npos);
  std::string unknown = kPcdHeader;
  unknown.replace(unknown.find("TYPE F F F U"), 12, "TYPE F F F Q");
  EXPECT_NE(error_of(read_pcd, write("u.pcd", unknown + "DATA ascii\n")).find("unknown type"),
            std::string::npos);
  std::string no_z = kPcdHeader;
  no_z.replace(no_z.find("FIELDS x y z"), 12, "FIELDS x y w");
  EXPECT_NE(error_of(read_pcd, write("z.pcd", no_z + "DATA ascii\n1 2 3 4\n1 2 3 4\n1 2 3 4\n")).find("'z'"),
            std::string::npos);
  EXPECT_NE(error_of(read_pcd, write("d.pcd", kPcdHeader + "DATA zip\n")).find("DATA type"),
            std::string::npos);
}

const std::string kPlyVertex =
    "element vertex 2\nproperty float x\nproperty float y\nproperty double z\n"
    "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
    "end_header\n";

TEST_F(PointReaders, PlyAscii) {
  const LoadedCloud cloud =
      read_ply(write("a.ply", "ply\nformat ascii 1.0\ncomment made by hand\n" + kPlyVertex +
                                  "1 2 3 255\n4 5 6 0\n"
                                  "3 0 1 1\n"));
  ASSERT_EQ(cloud.points.size(), 2U);
  EXPECT_EQ(cloud.points[1], Eigen::Vector3d(4, 5, 6));
}

TEST_F(PointReaders, PlyBinaryBothEndians) {
  for (const bool big : {false, true}) {
    std::string data;
    data += bytes_of(1.5f, big) + bytes_of(2.f, big) + bytes_of(3.0, big) + '\x01';
    data += bytes_of(std::nanf(""), big) + bytes_of(5.f, big) + bytes_of(6.0, big) + '\x02';
    const std::string format = big ? "binary_big_endian" : "binary_little_endian";
    const LoadedCloud cloud =
        read_ply(write(format + ".ply", "ply\nformat " + format + " 1.0\n" + kPlyVertex + data));
    ASSERT_EQ(cloud.points.size(), 1U) << format;
    EXPECT_EQ(cloud.dropped_non_finite, 1U);
    EXPECT_EQ(cloud.points[0], Eigen::Vector3d(1.5, 2, 3)) << format;
  }
}

TEST_F(PointReaders, PlyElementBeforeVerticesIsSkipped) {
  const LoadedCloud cloud =
      read_ply(write("e.ply",
                     "ply\nformat ascii 1.0\nelement camera 1\nproperty list uchar float k\nproperty int id\n"
                     "element vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
                     "2 0.5 0.5 7\n9 8 7\n"));
  ASSERT_EQ(cloud.points.size(), 1U);
  EXPECT_EQ(cloud.points[0], Eigen::Vector3d(9, 8, 7));
}

TEST_F(PointReaders, PlyErrors) {
  EXPECT_NE(error_of(read_ply, write("m.ply", "PLY?\n")).find("not a PLY"), std::string::npos);
  EXPECT_NE(
      error_of(read_ply, write("f.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n")).find("format"),
      std::string::npos);
  EXPECT_NE(error_of(read_ply, write("t.ply", "ply\nformat ascii 1.0\n" + kPlyVertex + "1 2 3 4\n"))
                .find("truncated"),
            std::string::npos);
  EXPECT_NE(error_of(read_ply, write("b.ply", "ply\nformat binary_little_endian 1.0\n" + kPlyVertex + "abc"))
                .find("truncated"),
            std::string::npos);
  EXPECT_NE(error_of(read_ply, write("h.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"))
                .find("end_header"),
            std::string::npos);
  EXPECT_NE(error_of(read_ply, write("y.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                     "property float z\nend_header\n1 2\n"))
                .find("'y'"),
            std::string::npos);
  EXPECT_NE(error_of(read_ply, write("ty.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\n"
                                     "end_header\n"))
                .find("unknown type"),
            std::string::npos);
}

TEST_F(PointReaders, CsvWithHeaderAndWhitespaceWithout) {
  const LoadedCloud csv = read_xyz(write("a.csv", "nx,x,y,z\n0.5 , 1 , 2 , 3\n0,nan,1,1\n0,4,5,6\n"));
  ASSERT_EQ(csv.points.size(), 2U);
  EXPECT_EQ(csv.dropped_non_finite, 1U);
  EXPECT_EQ(csv.points[0], Eigen::Vector3d(1, 2, 3));
  const LoadedCloud xyz = read_xyz(write("b.xyz", "# comment\n   2.5e+00   -1 3\n\n4 5 6 7\n"));
  ASSERT_EQ(xyz.points.size(), 2U);
  EXPECT_EQ(xyz.points[0], Eigen::Vector3d(2.5, -1, 3));
  EXPECT_NE(error_of(read_xyz, write("c.csv", "a,b,c\n1,2,3\n")).find("'x'"), std::string::npos);
  EXPECT_NE(error_of(read_xyz, write("d.xyz", "1 2 3\n1 2\n")).find("line 2"), std::string::npos);
  EXPECT_NE(error_of(read_xyz, write("e.xyz", "1 2 3\n1 2 zz\n")).find("'zz'"), std::string::npos);
}

TEST_F(PointReaders, ThreeDtkScanAndPoseConvertToMetresAndRightHanded) {
  // 3DTK: x right, y up, z forward, cm. Strata: x forward, y left, z up, m.
  const LoadedCloud scan = read_3dtk_scan(write("s.3d", "100 50 200\n0 0 3276.5\n10 20 30\n"));
  ASSERT_EQ(scan.points.size(), 2U);  // the max-range reading is dropped
  EXPECT_TRUE(scan.points[0].isApprox(Eigen::Vector3d(2.0, -1.0, 0.5)));
  // A pose turned 90 degrees about 3DTK's y (up) axis: positive theta_y turns forward (z) toward x
  // (right) in 3DTK's rotation matrix, i.e. to the right: a negative yaw in Strata's frame.
  const Eigen::Isometry3d pose = read_3dtk_pose(write("s.pose", "100 0 300\n0 90 0\n"));
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(3.0, -1.0, 0.0)));
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-12);
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY(), 1e-12));
  EXPECT_NE(error_of([](const fs::path& p) { return read_3dtk_pose(p); }, write("b.pose", "1 2\n"))
                .find("two lines"),
            std::string::npos);
  EXPECT_NE(
      error_of([](const fs::path& p) { return read_3dtk_scan(p); }, write("b.3d", "1 2\n")).find("line 1"),
      std::string::npos);
}

TEST_F(PointReaders, ThreeDtkFramesTakesTheLastMatrix) {
  // Column-major: translation in elements 13-15.
  const std::string identity_at_origin = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 1 0 1\n";
  const std::string moved = "1 0 0 0 0 1 0 0 0 0 1 0 10 20 300 1\n1 1 0 1\n";
  const Eigen::Isometry3d pose = read_3dtk_frames(write("s.frames", identity_at_origin + moved));
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(3.0, -0.1, 0.2)));
  EXPECT_NE(error_of([](const fs::path& p) { return read_3dtk_frames(p); }, write("e.frames", "1 2 3\n"))
                .find("16 numbers"),
            std::string::npos);
}

TEST_F(PointReaders, DispatchByExtension) {
  EXPECT_EQ(read_point_cloud(write("p.TXT", "1 2 3\n")).points.size(), 1U);
  EXPECT_NE(error_of(read_point_cloud, write("p.las", "")).find("unknown point cloud format"),
            std::string::npos);
  EXPECT_NE(error_of(read_point_cloud, dir_ / "missing.pcd").find("cannot open"), std::string::npos);
}

}  // namespace
}  // namespace strata::io
