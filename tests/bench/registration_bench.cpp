// strata_registration_bench: measures scan registration on the real pairs in STRATA_DATA_DIR against the
// issue's targets (accuracy, robustness, speed, search structure vs brute force). Not a test: it prints
// one machine-readable line per measurement, "key=value" separated by spaces, first word the kind.
//
//   strata_registration_bench [--data DIR] [--trials N] [--variants] [--search]
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <nanoflann.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/ann/brute_force.hpp"
#include "core/ann/kdtree.hpp"
#include "core/ann/voxel_hash_map.hpp"
#include "core/points/voxel_downsample.hpp"
#include "core/registration/register_scan.hpp"
#include "drivers/io/point_cloud_file.hpp"
#include "drivers/io/threedtk_reader.hpp"

namespace {

using strata::PointCloud;
using strata::RegistrationOptions;
using strata::RegistrationResult;
namespace fs = std::filesystem;
constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct Pair {
  std::string name;
  PointCloud source;
  PointCloud target;
  Eigen::Isometry3d guess;       ///< the starting guess that comes with the data (odometry, tutorial)
  Eigen::Isometry3d reference;   ///< the published registration (pcl_room: our own converged result)
  double max_translation_error;  ///< the issue's accuracy target, metres
  double max_rotation_error;     ///< radians
  /// pcl_room has no ground truth, only the README's yaw and translation from an independent ICP. Accuracy
  /// is checked against those; robustness is then measured around this program's own converged result
  /// (the README value leaves out roll and pitch, which are ~1 degree here).
  bool reference_is_sanity_value = false;
};

struct Error {
  double translation;
  double rotation;
};

Error error_between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return {d.translation().norm(), Eigen::AngleAxisd(d.rotation()).angle()};
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<Pair> load_pairs(const fs::path& data) {
  using strata::io::read_3dtk_frames;
  using strata::io::read_3dtk_pose;
  using strata::io::read_point_cloud;
  std::vector<Pair> pairs;
  const fs::path dtk = data / "3dtk_dat";
  if (fs::exists(dtk / "scan000.3d")) {
    std::vector<PointCloud> scans;
    std::vector<Eigen::Isometry3d> odometry;
    std::vector<Eigen::Isometry3d> reference;
    for (int i = 0; i < 3; ++i) {
      const std::string stem = "scan00" + std::to_string(i);
      scans.push_back(read_point_cloud(dtk / (stem + ".3d")).points);
      odometry.push_back(read_3dtk_pose(dtk / (stem + ".pose")));
      reference.push_back(read_3dtk_frames(dtk / "reference_slam6d_2009" / (stem + ".frames")));
    }
    const auto add = [&](int source, int target) {
      pairs.push_back({"3dtk_" + std::to_string(source) + "_to_" + std::to_string(target), scans[source],
                       scans[target], odometry[target].inverse() * odometry[source],
                       reference[target].inverse() * reference[source], 0.05, 0.3 * kDeg});
    };
    add(1, 0);
    add(2, 1);
    add(2, 0);
  }
  const fs::path car = data / "pairs" / "libpointmatcher_car";
  if (fs::exists(car / "car_cloud400.csv")) {
    Eigen::Matrix4d g;
    g << 0.981715, 0.169605, -0.0864239, 0.0614127, -0.152902, 0.973034, 0.172703, 0.191433, 0.113385,
        -0.15633, 0.981175, -0.0338571, 0, 0, 0, 1;  // carCloudList.csv, car_cloud401
    Eigen::Isometry3d reference(g);
    reference.linear() = Eigen::Quaterniond(reference.rotation()).normalized().toRotationMatrix();
    pairs.push_back({"car_401_to_400", read_point_cloud(car / "car_cloud401.csv").points,
                     read_point_cloud(car / "car_cloud400.csv").points, Eigen::Isometry3d::Identity(),
                     reference, 0.05, 0.5 * kDeg});
  }
  const fs::path room = data / "pairs" / "pcl_room";
  if (fs::exists(room / "room_scan1.pcd")) {
    Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
    guess.translate(Eigen::Vector3d(1.79387, 0.720047, 0.0));
    guess.rotate(Eigen::AngleAxisd(0.6931, Eigen::Vector3d::UnitZ()));
    // No ground truth: the reference is the README's independent ICP result (a sanity value, not truth).
    Eigen::Isometry3d sanity = Eigen::Isometry3d::Identity();
    sanity.translate(Eigen::Vector3d(1.975, 0.059, 0.027));
    sanity.rotate(Eigen::AngleAxisd(40.8 * kDeg, Eigen::Vector3d::UnitZ()));
    pairs.push_back({"room_2_to_1", read_point_cloud(room / "room_scan2.pcd").points,
                     read_point_cloud(room / "room_scan1.pcd").points, guess, sanity, 0.05, 0.5 * kDeg,
                     true});
  }
  return pairs;
}

/// Accuracy from the data's own guess, and the time of downsampling + registration (median of runs).
RegistrationResult accuracy_and_speed(Pair& pair, const RegistrationOptions& options,
                                      const std::string& variant, int runs) {
  std::vector<double> times;
  RegistrationResult result;
  for (int i = 0; i < runs; ++i) {
    result = strata::register_scan(pair.source, pair.target, pair.guess, options);
    times.push_back(result.seconds);
  }
  std::sort(times.begin(), times.end());
  Error e = error_between(pair.reference, result.refined);
  if (pair.reference_is_sanity_value) {
    const Eigen::Vector3d ypr_ref = pair.reference.rotation().eulerAngles(2, 1, 0);
    const Eigen::Vector3d ypr_got = result.refined.rotation().eulerAngles(2, 1, 0);
    e = {(pair.reference.translation() - result.refined.translation()).norm(),
         std::abs(ypr_ref.x() - ypr_got.x())};
    if (variant == "default") {
      pair.reference = result.refined;
      pair.reference_is_sanity_value = false;
    }
  }
  const bool pass = e.translation <= pair.max_translation_error && e.rotation <= pair.max_rotation_error;
  const Eigen::Vector3d t = result.refined.translation();
  const Eigen::Vector3d ypr = result.refined.rotation().eulerAngles(2, 1, 0) / kDeg;
  std::printf(
      "accuracy variant=%s pair=%s err_cm=%.2f err_deg=%.3f target_cm=%.1f target_deg=%.2f pass=%d "
      "verdict=%s "
      "reason=%s rmse_m=%.4f pairs=%zu source_pts=%zu target_pts=%zu iterations=%d tx=%.4f ty=%.4f tz=%.4f "
      "yaw_deg=%.3f\n",
      variant.c_str(), pair.name.c_str(), 100 * e.translation, e.rotation / kDeg,
      100 * pair.max_translation_error, pair.max_rotation_error / kDeg, pass ? 1 : 0,
      std::string(strata::to_string(result.assessment.verdict)).c_str(),
      std::string(strata::to_string(result.assessment.reason)).c_str(), result.rmse, result.pairs,
      result.source_points, result.target_points, result.iterations, t.x(), t.y(), t.z(), ypr.x());
  std::printf("speed variant=%s pair=%s source_raw=%zu target_raw=%zu median_ms=%.2f min_ms=%.2f runs=%d\n",
              variant.c_str(), pair.name.c_str(), pair.source.size(), pair.target.size(),
              1e3 * times[times.size() / 2], 1e3 * times.front(), runs);
  return result;
}

Eigen::Isometry3d random_offset(std::mt19937& rng, double max_translation, double max_rotation) {
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Vector3d direction = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.translation() = direction * max_translation * uniform(rng);
  offset.linear() = Eigen::AngleAxisd(max_rotation * uniform(rng), axis).toRotationMatrix();
  return offset;
}

/// Registrations from random guesses around the reference: how many converge, and how many wrong results
/// fault control lets through. A result is right within 10 cm and 1 degree of the reference.
void robustness(const Pair& pair, const RegistrationOptions& options, const std::string& variant, int trials,
                double max_translation, double max_rotation, const std::string& label) {
  strata::ScanRegistration registration(options);
  registration.set_target(pair.target);
  std::mt19937 rng(42);
  int converged = 0;
  int accepted = 0;
  int accepted_wrong = 0;
  int rejected_right = 0;
  double seconds = 0.0;
  for (int i = 0; i < trials; ++i) {
    const Eigen::Isometry3d guess = pair.reference * random_offset(rng, max_translation, max_rotation);
    const RegistrationResult result = registration.register_scan(pair.source, guess);
    seconds += result.seconds;
    const Error e = error_between(pair.reference, result.refined);
    const bool right = e.translation <= 0.10 && e.rotation <= 1.0 * kDeg;
    converged += right ? 1 : 0;
    accepted += result.accepted() ? 1 : 0;
    accepted_wrong += (result.accepted() && !right) ? 1 : 0;
    rejected_right += (!result.accepted() && right) ? 1 : 0;
  }
  std::printf(
      "robustness variant=%s pair=%s range=%s max_m=%.2f max_deg=%.1f trials=%d converged_pct=%.1f "
      "accepted_pct=%.1f accepted_wrong_pct=%.1f rejected_right_pct=%.1f mean_ms=%.2f\n",
      variant.c_str(), pair.name.c_str(), label.c_str(), max_translation, max_rotation / kDeg, trials,
      100.0 * converged / trials, 100.0 * accepted / trials, 100.0 * accepted_wrong / trials,
      100.0 * rejected_right / trials, 1e3 * seconds / trials);
  std::fflush(stdout);
}

/// nanoflann over a PointCloud: what core/ann/kdtree.cpp replaced, measured here against it.
struct NanoflannCloud {
  const PointCloud* points;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] double kdtree_get_pt(std::size_t index, std::size_t dim) const {
    return (*points)[index][static_cast<Eigen::Index>(dim)];
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox& /*unused*/) const {
    return false;
  }
};
using NanoflannTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, NanoflannCloud>, NanoflannCloud,
                                        3, std::size_t>;

/// The closest point within a bound, for nanoflann (as core/ann/kdtree.cpp had it).
class NanoflannBoundedNearest {
 public:
  using DistanceType = double;
  using IndexType = std::size_t;
  using CountType = std::size_t;
  explicit NanoflannBoundedNearest(double max_squared) : worst_(max_squared) {}
  [[nodiscard]] bool full() const { return true; }
  bool addPoint(double squared, std::size_t index) {
    worst_ = squared;
    index_ = index;
    found_ = true;
    return true;
  }
  [[nodiscard]] double worstDist() const { return worst_; }
  [[nodiscard]] bool found() const { return found_; }

 private:
  double worst_;
  std::size_t index_ = 0;
  bool found_ = false;
};

/// Nearest-neighbour search over a whole real scan, every source point as a query, bounded at 0.25 m (the
/// thesis measurement): brute force vs the kd-tree vs nanoflann vs the voxel hash, build time included.
/// kdtree_query_pct_of_brute leaves the build out: ICP builds the tree once and searches it in every
/// iteration (thesis 4.1.1), so a registration's searches cost the queries' share many times over.
void search_comparison(const Pair& pair) {
  const PointCloud& source = pair.source;
  const PointCloud& target = pair.target;
  PointCloud queries;
  for (const Eigen::Vector3d& p : source)
    queries.push_back(pair.guess * p);
  const double bound = 0.25;
  std::size_t found_brute = 0;
  auto start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries)
    found_brute += strata::brute_force_nearest(target, q, bound) ? 1 : 0;
  const double brute = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const strata::KdTree tree(target);
  const double tree_build = seconds_since(start);
  std::size_t found_tree = 0;
  start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries)
    found_tree += tree.nearest(q, bound) ? 1 : 0;
  const double tree_query = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const NanoflannCloud cloud{&target};
  const NanoflannTree nanoflann_tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  const double nanoflann_build = seconds_since(start);
  std::size_t found_nanoflann = 0;
  start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries) {
    NanoflannBoundedNearest result(bound * bound);
    nanoflann_tree.findNeighbors(result, q.data(), nanoflann::SearchParams());
    found_nanoflann += result.found() ? 1 : 0;
  }
  const double nanoflann_query = seconds_since(start);

  start = std::chrono::steady_clock::now();
  const strata::VoxelHashMap hash(target, bound);
  const double hash_build = seconds_since(start);
  std::size_t found_hash = 0;
  start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries)
    found_hash += hash.nearest(q, bound) ? 1 : 0;
  const double hash_query = seconds_since(start);

  // Metre-scale bound, as in the first coarse-to-fine stage.
  start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries)
    static_cast<void>(tree.nearest(q, 1.5));
  const double tree_coarse = seconds_since(start);
  const strata::VoxelHashMap coarse_hash(target, 0.5);
  start = std::chrono::steady_clock::now();
  for (const Eigen::Vector3d& q : queries)
    static_cast<void>(coarse_hash.nearest(q, 1.5));
  const double hash_coarse = seconds_since(start);

  std::printf(
      "search pair=%s queries=%zu points=%zu bound_m=%.2f brute_ms=%.1f kdtree_build_ms=%.2f "
      "kdtree_query_ms=%.2f kdtree_pct_of_brute=%.3f kdtree_query_pct_of_brute=%.3f nanoflann_build_ms=%.2f "
      "nanoflann_query_ms=%.2f "
      "nanoflann_pct_of_brute=%.3f voxelhash_build_ms=%.2f voxelhash_query_ms=%.2f "
      "voxelhash_pct_of_brute=%.3f found_brute=%zu found_kdtree=%zu found_nanoflann=%zu found_voxelhash=%zu "
      "kdtree_query_1.5m_ms=%.2f voxelhash_query_1.5m_ms=%.2f\n",
      pair.name.c_str(), queries.size(), target.size(), bound, 1e3 * brute, 1e3 * tree_build,
      1e3 * tree_query, 100.0 * (tree_build + tree_query) / brute, 100.0 * tree_query / brute,
      1e3 * nanoflann_build, 1e3 * nanoflann_query, 100.0 * (nanoflann_build + nanoflann_query) / brute,
      1e3 * hash_build, 1e3 * hash_query, 100.0 * (hash_build + hash_query) / brute, found_brute, found_tree,
      found_nanoflann, found_hash, 1e3 * tree_coarse, 1e3 * hash_coarse);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path data = STRATA_DATA_DIR;
  int trials = 100;
  bool variants = false;
  bool search = false;
  std::vector<std::string> only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (arg == "--trials" && i + 1 < argc)
      trials = std::stoi(argv[++i]);
    else if (arg == "--variants")
      variants = true;
    else if (arg == "--search")
      search = true;
    else if (arg == "--pair" && i + 1 < argc)
      only.emplace_back(argv[++i]);
    else {
      std::fprintf(stderr, "usage: %s [--data DIR] [--trials N] [--variants] [--search] [--pair NAME]...\n",
                   argv[0]);
      return 2;
    }
  }
  std::vector<Pair> pairs = load_pairs(data);
  if (!only.empty())
    std::erase_if(pairs,
                  [&](const Pair& p) { return std::find(only.begin(), only.end(), p.name) == only.end(); });
  if (pairs.empty()) {
    std::printf("skipped reason=no_data data_dir=%s\n", data.c_str());
    return 0;
  }

  std::vector<std::pair<std::string, RegistrationOptions>> configs{{"default", {}}};
  if (variants) {
    RegistrationOptions p2p;
    // Session 5's defaults: the thesis's MSE stop, one source density, a 5 cm target, every pair checked.
    RegistrationOptions mse_stop;
    mse_stop.stages = {
        {.max_correspondence_distance = 1.0,
         .source_voxel_size = 0.3,
         .mse_change_threshold = 1e-5,
         .max_iterations = 30},
        {.max_correspondence_distance = 0.25,
         .source_voxel_size = 0.3,
         .mse_change_threshold = 2e-6,
         .max_iterations = 30},
    };
    mse_stop.target_voxel_size = 0.05;
    mse_stop.max_constraint_pairs = 0;
    configs.emplace_back("mse_stop_5cm_target", mse_stop);
    RegistrationOptions polar = p2p;
    polar.icp.rotation_solver = strata::RotationSolver::kPolarDenmanBeavers;
    configs.emplace_back("point_to_point_polar", polar);
    RegistrationOptions thesis = p2p;
    thesis.stages = {
        {.max_correspondence_distance = 0.25, .source_voxel_size = 0.3, .mse_change_threshold = 1e-5}};
    configs.emplace_back("point_to_point_single_0.25", thesis);
    RegistrationOptions plane;
    plane.icp.metric = strata::IcpMetric::kPointToPlane;
    configs.emplace_back("point_to_plane_plain", plane);
    RegistrationOptions plane_kernel;
    plane_kernel.icp.metric = strata::IcpMetric::kPointToPlane;
    plane_kernel.icp.kernel_scale = 0.1;
    configs.emplace_back("point_to_plane_geman_mcclure_0.1", plane_kernel);
    RegistrationOptions p2p_kernel;
    p2p_kernel.icp.kernel_scale = 0.1;
    configs.emplace_back("point_to_point_geman_mcclure_0.1", p2p_kernel);
  }
  for (auto& [variant, options] : configs) {
    for (Pair& pair : pairs) {
      accuracy_and_speed(pair, options, variant, 11);
      std::fflush(stdout);
    }
  }
  for (auto& [variant, options] : configs) {
    for (const Pair& pair : pairs) {
      robustness(pair, options, variant, trials, 0.5, 10.0 * kDeg, "small");
      if (variant == "default")
        robustness(pair, options, variant, trials, 3.0, 60.0 * kDeg, "large");
    }
  }
  if (search) {
    for (const Pair& pair : pairs)
      search_comparison(pair);
  }
  return 0;
}
