// MovingAI .map/.scen and map_server PGM + YAML readers: small files written here, the real data when
// present, and the errors bad files give.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/mls/map_export.hpp"
#include "drivers/io/map_file_error.hpp"
#include "drivers/io/map_server_reader.hpp"
#include "drivers/io/movingai_reader.hpp"

namespace strata::io {
namespace {

namespace fs = std::filesystem;

fs::path data_dir() {
  const char* from_env = std::getenv("STRATA_DATA_DIR");
  return from_env != nullptr ? fs::path(from_env) : fs::path(STRATA_DATA_DIR);
}

/// A scratch directory removed at the end of the test.
class GridMapReaders : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("strata_grid_readers_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& content) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }
  /// The message of the MapFileError `read` throws (fails the test if it throws none).
  template <typename Read>
  std::string error_of(Read read) {
    try {
      read();
    } catch (const MapFileError& error) {
      return error.what();
    }
    ADD_FAILURE() << "no MapFileError";
    return {};
  }
  fs::path dir_;
};

// The drivable map's ROS download, read back as a planner's map: one grid geometry, so every cell and
// every map-frame point lands where it was.
TEST_F(GridMapReaders, TheRosMapWeWriteReadsBackCellForCell) {
  LevelGrid level;
  level.origin = {-3.2, 1.7};
  level.resolution = 0.1;
  level.width = 7;
  level.height = 5;
  const Occupancy kinds[] = {Occupancy::free, Occupancy::occupied, Occupancy::unknown};
  for (std::size_t i = 0; i < level.cell_count(); ++i)
    level.cells.push_back(kinds[(i * i + i / 3) % 3]);  // no symmetry a flip could keep
  const fs::path yaml = dir_ / "level.yaml";
  write_ros_map(level, yaml);

  const OccupancyGrid grid = read_map_server_map(yaml);
  ASSERT_EQ(grid.width, level.width);
  ASSERT_EQ(grid.height, level.height);
  EXPECT_DOUBLE_EQ(grid.resolution, level.resolution);
  EXPECT_TRUE(grid.origin.isApprox(level.origin));
  for (int y = 0; y < level.height; ++y)
    for (int x = 0; x < level.width; ++x) {
      const Occupancy expected = level.at(x, y);
      const CellState read = grid.at({x, y});
      EXPECT_EQ(read, expected == Occupancy::free       ? CellState::free
                      : expected == Occupancy::occupied ? CellState::occupied
                                                        : CellState::unknown)
          << x << "," << y;
      const Eigen::Vector2d centre = grid.center_of({x, y});
      EXPECT_EQ(level.at_position(centre.x(), centre.y()), expected);
    }
}

TEST_F(GridMapReaders, MovingAiMapTerrainAndAppendedText) {
  const fs::path path = write("small.map",
                              "type octile\nheight 2\nwidth 4\nmap\n"
                              ".GS@\r\nOTW.\n"
                              "@article{sturtevant2012, title={Benchmarks}}\n");
  const OccupancyGrid grid = read_movingai_map(path);
  ASSERT_EQ(grid.width, 4);
  ASSERT_EQ(grid.height, 2);
  EXPECT_EQ(grid.resolution, 1.0);
  EXPECT_EQ(grid.at({0, 0}), CellState::free);
  EXPECT_EQ(grid.at({1, 0}), CellState::free);
  EXPECT_EQ(grid.at({2, 0}), CellState::free);      // swamp
  EXPECT_EQ(grid.at({3, 0}), CellState::occupied);  // @
  EXPECT_EQ(grid.at({0, 1}), CellState::occupied);  // O
  EXPECT_EQ(grid.at({1, 1}), CellState::occupied);  // tree
  EXPECT_EQ(grid.at({2, 1}), CellState::occupied);  // water
  EXPECT_EQ(grid.at({3, 1}), CellState::free);
}

TEST_F(GridMapReaders, BadMovingAiMapsNameTheFileAndTheProblem) {
  const fs::path no_header = write("no_header.map", "....\n....\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_map(no_header); }).find("no_header.map"), std::string::npos);
  const fs::path bad_char = write("bad_char.map", "type octile\nheight 1\nwidth 3\nmap\n.x.\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_map(bad_char); }).find("unknown terrain character 'x'"),
            std::string::npos);
  const fs::path short_row = write("short_row.map", "type octile\nheight 2\nwidth 3\nmap\n...\n..\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_map(short_row); }).find("has 2 cells"), std::string::npos);
  const fs::path few_rows = write("few_rows.map", "type octile\nheight 3\nwidth 3\nmap\n...\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_map(few_rows); }).find("ends after 1"), std::string::npos);
  const fs::path bad_size = write("bad_size.map", "type octile\nheight -2\nwidth 3\nmap\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_map(bad_size); }).find("positive integer"), std::string::npos);
  EXPECT_NE(error_of([&] { (void)read_movingai_map(dir_ / "missing.map"); }).find("cannot open"),
            std::string::npos);
}

TEST_F(GridMapReaders, MovingAiScenarioSkipsLinesWithoutNineFields) {
  const fs::path path =
      write("small.scen",
            "version 1\n"
            "0\tsmall.map\t4\t2\t0\t0\t3\t1\t3.41421356\n"
            "\n"
            "3 small.map 4 2 1 0 1 0 0\n"
            "@article{sturtevant2012,\n  title={Benchmarks for Grid-Based Pathfinding},\n}\n");
  const MovingAiScenario scenario = read_movingai_scenario(path);
  ASSERT_EQ(scenario.queries.size(), 2U);
  EXPECT_EQ(scenario.skipped_lines, 3U);
  EXPECT_EQ(scenario.queries[0].map, "small.map");
  EXPECT_EQ(scenario.queries[0].map_width, 4);
  EXPECT_EQ(scenario.queries[0].start, (GridCell{0, 0}));
  EXPECT_EQ(scenario.queries[0].goal, (GridCell{3, 1}));
  EXPECT_DOUBLE_EQ(scenario.queries[0].optimal_length, 3.41421356);
  EXPECT_EQ(scenario.queries[1].bucket, 3);

  const fs::path no_version = write("no_version.scen", "0 small.map 4 2 0 0 3 1 3\n");
  EXPECT_NE(error_of([&] { (void)read_movingai_scenario(no_version); }).find("version"), std::string::npos);
  const fs::path bad_number = write("bad_number.scen", "version 1\n0 small.map 4 2 0 zero 3 1 3\n");
  const std::string message = error_of([&] { (void)read_movingai_scenario(bad_number); });
  EXPECT_NE(message.find("bad_number.scen: line 2"), std::string::npos) << message;
}

TEST_F(GridMapReaders, RealAnonsarFilesWithAppendedBibtex) {
  const fs::path dir = data_dir() / "movingai/anonsar_dao_arena";
  if (!fs::exists(dir / "arena.map"))
    GTEST_SKIP() << "MovingAI data not found at " << dir << " (set STRATA_DATA_DIR)";
  const OccupancyGrid grid = read_movingai_map(dir / "arena.map");
  EXPECT_EQ(grid.width, 49);
  EXPECT_EQ(grid.height, 49);
  std::size_t free_cells = 0;
  for (const CellState cell : grid.cells)
    free_cells += cell == CellState::free ? 1 : 0;
  EXPECT_EQ(free_cells, 2054U);  // the data README's count of '.'
  const MovingAiScenario scenario = read_movingai_scenario(dir / "arena.map.scen");
  EXPECT_EQ(scenario.queries.size(), 130U);
  EXPECT_GT(scenario.skipped_lines, 0U);
}

TEST_F(GridMapReaders, MapServerBinaryPgmWithNegateAndThresholds) {
  // 3 x 2 image, top row first: with negate 1, 255 is occupied and 0 free; 100/255 = 0.39 is unknown.
  std::string pgm = "P5\n# made by the test\n3 2\n255\n";
  for (const int v : {0, 255, 100, 255, 0, 0})
    pgm.push_back(static_cast<char>(v));
  write("map.pgm", pgm);
  const fs::path yaml = write("map.yaml",
                              "image: map.pgm  # relative to this file\n"
                              "resolution: 0.05\n"
                              "origin: [-1.0, 2.5, 0.0]\n"
                              "negate: 1\n"
                              "occupied_thresh: 0.65\n"
                              "free_thresh: 0.196\n");
  const OccupancyGrid grid = read_map_server_map(yaml);
  ASSERT_EQ(grid.width, 3);
  ASSERT_EQ(grid.height, 2);
  EXPECT_DOUBLE_EQ(grid.resolution, 0.05);
  EXPECT_DOUBLE_EQ(grid.origin.x(), -1.0);
  EXPECT_DOUBLE_EQ(grid.origin.y(), 2.5);
  // The image's top row is the grid's top (last) row.
  EXPECT_EQ(grid.at({0, 1}), CellState::free);
  EXPECT_EQ(grid.at({1, 1}), CellState::occupied);
  EXPECT_EQ(grid.at({2, 1}), CellState::unknown);
  EXPECT_EQ(grid.at({0, 0}), CellState::occupied);
  EXPECT_EQ(grid.at({1, 0}), CellState::free);
  EXPECT_EQ(grid.cell_of({-0.99, 2.51}), (GridCell{0, 0}));
}

TEST_F(GridMapReaders, MapServerAsciiPgmWithoutNegate) {
  write("ascii.pgm", "P2\n2 1\n15\n15 0\n");  // white free, black occupied
  const fs::path yaml =
      write("ascii.yaml", "image: \"ascii.pgm\"\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\n");
  const OccupancyGrid grid = read_map_server_map(yaml);
  ASSERT_EQ(grid.width, 2);
  EXPECT_EQ(grid.at({0, 0}), CellState::free);
  EXPECT_EQ(grid.at({1, 0}), CellState::occupied);
}

TEST_F(GridMapReaders, BadMapServerFilesNameTheFileAndTheProblem) {
  const fs::path no_resolution = write("no_resolution.yaml", "image: x.pgm\norigin: [0, 0, 0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_yaml(no_resolution); }).find("missing resolution"),
            std::string::npos);
  const fs::path bad_origin = write("bad_origin.yaml", "image: x.pgm\nresolution: 0.1\norigin: [0, 0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_yaml(bad_origin); }).find("origin"), std::string::npos);
  const fs::path bad_resolution =
      write("bad_resolution.yaml", "image: x.pgm\nresolution: -1\norigin: [0,0,0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_yaml(bad_resolution); }).find("positive"),
            std::string::npos);
  const fs::path bad_mode =
      write("bad_mode.yaml", "image: x.pgm\nresolution: 1\norigin: [0,0,0]\nmode: fancy\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_yaml(bad_mode); }).find("mode"), std::string::npos);

  write("truncated.pgm", "P5 4 4 255\n" + std::string(5, '\0'));
  const fs::path truncated =
      write("truncated.yaml", "image: truncated.pgm\nresolution: 1\norigin: [0,0,0]\n");
  const std::string message = error_of([&] { (void)read_map_server_map(truncated); });
  EXPECT_NE(message.find("truncated.pgm"), std::string::npos) << message;
  EXPECT_NE(message.find("truncated PGM"), std::string::npos) << message;

  write("not.pgm", "P6\n1 1\n255\nabc");
  const fs::path colour = write("colour.yaml", "image: not.pgm\nresolution: 1\norigin: [0,0,0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_map(colour); }).find("not a PGM"), std::string::npos);
  const fs::path png = write("png.yaml", "image: map.png\nresolution: 1\norigin: [0,0,0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_map(png); }).find("only PGM"), std::string::npos);
  write("missing.yaml", "image: absent.pgm\nresolution: 1\norigin: [0,0,0]\n");
  EXPECT_NE(error_of([&] { (void)read_map_server_map(dir_ / "missing.yaml"); }).find("absent.pgm"),
            std::string::npos);
}

TEST_F(GridMapReaders, RealNav2BenchmarkMap) {
  const fs::path yaml = data_dir() / "nav2/100by100_20.yaml";
  if (!fs::exists(yaml))
    GTEST_SKIP() << "Nav2 map not found at " << yaml << " (set STRATA_DATA_DIR)";
  const OccupancyGrid grid = read_map_server_map(yaml);
  EXPECT_EQ(grid.width, 2000);
  EXPECT_EQ(grid.height, 2000);
  EXPECT_DOUBLE_EQ(grid.resolution, 0.05);
  std::size_t occupied = 0;
  for (const CellState cell : grid.cells)
    occupied += cell == CellState::occupied ? 1 : 0;
  EXPECT_NEAR(static_cast<double>(occupied) / static_cast<double>(grid.cells.size()), 0.206,
              0.001);  // README
}

}  // namespace
}  // namespace strata::io
