#include "scanbus/room_evaluation/room_evaluation.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <random>
#include <stdexcept>
#include <thread>

#include "scanbus/room_evaluation/simulated_scan.hpp"

namespace scanbus::room_evaluation {

namespace {

constexpr double kCornerMatch = 0.25;   // m: a measured wall is a true one when both ends are this near
constexpr double kMinSeenShare = 0.3;   // of a wall's length in view, and at least
constexpr double kMinSeenLength = 0.2;  // m, for the wall to count as seen

// The room's corners in the frame the measurement reports in: the scanner's, turned by the
// encoder's offset (the device reports yaw from its encoder's zero).
std::vector<Eigen::Vector2d> true_corners(const sim::GeneratedRoom& generated) {
  const sim::RoomModel& room = generated.room;
  const Eigen::Rotation2Dd to_scanner(-room.heading - generated.hardware.errors.encoder_offset);
  std::vector<Eigen::Vector2d> corners;
  for (const auto& c : room.corners) corners.push_back(to_scanner * (c - room.scanner.head<2>()));
  return corners;
}

// Matched walls, or nothing when a measured wall is no true wall or two are the same one.
std::optional<std::vector<WallCheck>> match_walls(const room_measurement::RoomResult& result,
                                                  const std::vector<Eigen::Vector2d>& truth) {
  const size_t n = truth.size(), m = result.walls.size();
  if (m != n) return std::nullopt;
  std::vector<bool> used(n, false);
  std::vector<WallCheck> checks;
  for (size_t i = 0; i < m; ++i) {
    const Eigen::Vector2d a = result.corners[i], b = result.corners[(i + 1) % m];
    std::optional<size_t> found;
    for (size_t j = 0; j < n && !found; ++j) {
      const Eigen::Vector2d c = truth[j], d = truth[(j + 1) % n];
      const bool same = ((a - c).norm() < kCornerMatch && (b - d).norm() < kCornerMatch) ||
                        ((a - d).norm() < kCornerMatch && (b - c).norm() < kCornerMatch);
      if (same && !used[j]) found = j;
    }
    if (!found) return std::nullopt;
    used[*found] = true;
    checks.push_back({(truth[(*found + 1) % n] - truth[*found]).norm(), result.walls[i].length,
                      result.walls[i].length_sigma, *found});
  }
  return checks;
}

// The matched walls' true openings against the measured ones (each measured opening placed on
// its true wall by where its ends lie, so a wall matched the other way round compares too).
void check_openings(const sim::RoomModel& room, const std::vector<Eigen::Vector2d>& truth,
                    const room_measurement::RoomResult& result, RoomCase& c) {
  constexpr double kFoundShare = 0.5;
  const size_t n = truth.size();
  for (size_t i = 0; i < c.walls.size(); ++i) {
    const size_t j = c.walls[i].true_wall;
    const Eigen::Vector2d origin = truth[j], along = (truth[(j + 1) % n] - truth[j]).normalized();
    const Eigen::Vector2d corner = result.corners[i];
    const Eigen::Vector2d direction = (result.corners[(i + 1) % result.corners.size()] - corner).normalized();
    std::vector<std::pair<double, double>> measured;
    for (const auto& o : result.walls[i].openings) {
      const double a = along.dot(corner + o.start * direction - origin);
      const double b = along.dot(corner + (o.start + o.width) * direction - origin);
      measured.emplace_back(std::min(a, b), std::max(a, b));
    }
    std::vector<bool> matched(measured.size(), false);
    for (const auto& truth_opening : room.openings) {
      if (truth_opening.wall != j) continue;
      OpeningCheck check{truth_opening.from, truth_opening.to};
      double best = 0;
      for (size_t k = 0; k < measured.size(); ++k) {
        const double overlap =
            std::min(measured[k].second, check.true_to) - std::max(measured[k].first, check.true_from);
        if (overlap <= 0) continue;
        matched[k] = true;
        if (overlap <= best) continue;
        best = overlap;
        check.from = measured[k].first;
        check.to = measured[k].second;
      }
      check.found = best >= kFoundShare * (check.true_to - check.true_from);
      c.openings.push_back(check);
    }
    c.spurious_openings += static_cast<size_t>(std::count(matched.begin(), matched.end(), false));
  }
}

double percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(std::ceil(fraction * values.size())) - 1)];
}

SweepSummary summary_of(const std::string& name, const std::vector<const RoomCase*>& cases) {
  SweepSummary s;
  s.category = name;
  std::vector<double> wall_errors, area_errors, opening_errors, corner_errors;
  size_t corner_one_sigma = 0, corner_two_sigma = 0;
  size_t one_sigma = 0, two_sigma = 0;
  for (const RoomCase* c : cases) {
    ++s.rooms;
    s.measurable += c->measurable;
    switch (c->verdict) {
      case Verdict::Measured:
        ++s.measured;
        break;
      case Verdict::Inferred:
        ++s.inferred;
        break;
      case Verdict::Wrong:
        ++s.wrong;
        break;
      case Verdict::Refused:
        ++s.refused;
        break;
      case Verdict::RefusedWrongly:
        ++s.refused_wrongly;
        break;
    }
    if (c->verdict == Verdict::Wrong || (c->verdict == Verdict::Measured && c->max_wall_error() > 0.02))
      ++s.ok_over_2cm;
    if (c->verdict == Verdict::Inferred) {  // wall errors and sigmas count; the 1 cm target is for seen rooms
      for (const auto& w : c->walls) {
        wall_errors.push_back(std::abs(w.error()));
        one_sigma += std::abs(w.error()) <= w.sigma;
        two_sigma += std::abs(w.error()) <= 2 * w.sigma;
      }
    }
    if (c->ceiling_height && c->true_ceiling_height) {
      const double e = std::abs(*c->ceiling_height - *c->true_ceiling_height);
      s.worst_ceiling_error = std::max(s.worst_ceiling_error.value_or(0.0), e);
    }
    for (size_t i = 0; i < c->corner_errors.size(); ++i) {
      corner_errors.push_back(c->corner_errors[i]);
      corner_one_sigma += c->corner_errors[i] <= c->corner_sigmas[i];
      corner_two_sigma += c->corner_errors[i] <= 2 * c->corner_sigmas[i];
    }
    s.spurious_openings += c->spurious_openings;
    for (const auto& o : c->openings) {
      ++s.true_openings;
      if (!o.found) continue;
      ++s.openings_found;
      opening_errors.push_back(o.edge_error());
    }
    if (c->verdict != Verdict::Measured) continue;
    const double area_error = std::abs(c->area - c->true_area) / c->true_area;
    area_errors.push_back(area_error);
    if (c->max_wall_error() <= 0.01 && area_error <= 0.005) ++s.within_target;
    for (const auto& w : c->walls) {
      wall_errors.push_back(std::abs(w.error()));
      one_sigma += std::abs(w.error()) <= w.sigma;
      two_sigma += std::abs(w.error()) <= 2 * w.sigma;
    }
  }
  s.walls = wall_errors.size();
  if (!wall_errors.empty()) {
    s.max_wall_error = *std::max_element(wall_errors.begin(), wall_errors.end());
    s.p95_wall_error = percentile(wall_errors, 0.95);
    s.median_wall_error = percentile(wall_errors, 0.5);
    s.within_1_sigma = static_cast<double>(one_sigma) / wall_errors.size();
    s.within_2_sigma = static_cast<double>(two_sigma) / wall_errors.size();
  }
  s.corners = corner_errors.size();
  if (!corner_errors.empty()) {
    s.median_corner_error = percentile(corner_errors, 0.5);
    s.max_corner_error = *std::max_element(corner_errors.begin(), corner_errors.end());
    s.corners_within_1_sigma = static_cast<double>(corner_one_sigma) / corner_errors.size();
    s.corners_within_2_sigma = static_cast<double>(corner_two_sigma) / corner_errors.size();
  }
  if (!opening_errors.empty()) {
    s.median_opening_error = percentile(opening_errors, 0.5);
    s.max_opening_error = *std::max_element(opening_errors.begin(), opening_errors.end());
  }
  if (!area_errors.empty()) {
    s.max_area_error = *std::max_element(area_errors.begin(), area_errors.end());
    s.p95_area_error = percentile(area_errors, 0.95);
  }
  return s;
}

}  // namespace

const char* verdict_name(Verdict verdict) {
  switch (verdict) {
    case Verdict::Measured:
      return "measured";
    case Verdict::Inferred:
      return "inferred";
    case Verdict::Wrong:
      return "wrong";
    case Verdict::Refused:
      return "refused";
    case Verdict::RefusedWrongly:
      return "refused_wrongly";
  }
  return "unknown";
}

double RoomCase::max_wall_error() const {
  double worst = 0;
  for (const auto& w : walls) worst = std::max(worst, std::abs(w.error()));
  return worst;
}

RoomCase evaluate_room(const sim::GeneratedRoom& generated, const room_measurement::RoomSettings& settings,
                       bool keep_cloud) {
  const sim::RoomModel& room = generated.room;
  RoomCase c;
  c.category = generated.category;
  c.seed = generated.seed;
  c.true_walls = room.corners.size();
  c.true_area = room.floor_area();
  c.true_ceiling_height = room.ceiling;
  const auto visibility = sim::wall_visibility(room);
  const auto lengths = room.wall_lengths();
  c.measurable = true;
  for (size_t i = 0; i < visibility.size(); ++i) {
    if (visibility[i] >= kMinSeenShare && visibility[i] * lengths[i] >= kMinSeenLength) continue;
    c.measurable = false;
    c.unseen += (c.unseen.empty() ? "wall " : ", ") + std::to_string(i + 1);
  }
  SimulatedScanSettings scan;
  scan.hardware = generated.hardware;
  auto points = simulated_scan(room, scan);
  c.measurement = room_measurement::measure_room(points, settings);
  const auto& result = c.measurement;
  c.points = points.size();
  if (keep_cloud) {
    c.cloud = std::move(points);
    c.room = room;
  }
  c.status = result.status;
  c.message = result.message;
  c.elapsed_ms = result.elapsed_ms;
  c.ceiling_height = result.ceiling_height();
  if (result.status != room_measurement::RoomStatus::Ok) {
    c.verdict = c.measurable ? Verdict::RefusedWrongly : Verdict::Refused;
    return c;
  }
  c.area = result.area;
  c.area_sigma = result.area_sigma;
  const auto truth = true_corners(generated);
  const auto matched = match_walls(result, truth);
  if (!matched) {
    c.verdict = Verdict::Wrong;
    return c;
  }
  c.walls = *matched;
  check_openings(room, truth, result, c);
  for (size_t i = 0; i < result.corners.size() && i < result.corner_sigmas.size(); ++i) {
    double nearest = std::numeric_limits<double>::max();  // matched walls put every corner near its true one
    for (const auto& t : truth) nearest = std::min(nearest, (result.corners[i] - t).norm());
    c.corner_errors.push_back(nearest);
    c.corner_sigmas.push_back(result.corner_sigmas[i]);
  }
  const bool inferred =
      std::any_of(result.walls.begin(), result.walls.end(), [](const auto& w) { return w.inferred(); });
  c.verdict = inferred ? Verdict::Inferred : Verdict::Measured;
  return c;
}

sim::HardwareSettings unit_of(unsigned unit_seed) {
  std::mt19937 random(unit_seed);
  return sim::draw_hardware(random);
}

SweepCalibration calibrate_on(const std::vector<RoomCase>& cases, unsigned unit_seed) {
  std::vector<room_measurement::DeviceEstimate> scans;
  for (const auto& c : cases)
    if (c.verdict == Verdict::Measured || c.verdict == Verdict::Inferred) scans.push_back(c.measurement.device);
  SweepCalibration s;
  s.calibration = room_measurement::calibrate_unit(scans);
  const auto unit = unit_of(unit_seed).errors;
  // Corrections undo the errors: a range read long is shortened; a pitch read short is increased.
  s.true_range_bias = -unit.range_bias;
  s.true_lever_arm = unit.lever_arm;
  s.true_pitch_offset = unit.servo_offset;
  return s;
}

std::vector<RoomCase> evaluate_sweep(const SweepOptions& options, const room_measurement::RoomSettings& settings,
                                     const std::function<void(size_t, size_t)>& progress) {
  const auto& categories = options.categories;
  if (categories.empty()) throw std::invalid_argument("evaluate_sweep: no room categories to sweep");
  std::vector<sim::GeneratedRoom> rooms;
  const int per_category = std::max(1, static_cast<int>((options.count + categories.size() - 1) / categories.size()));
  for (auto category : categories)
    for (int i = 0; i < per_category; ++i) {
      rooms.push_back(sim::generate_room(category, options.first_seed + static_cast<unsigned>(i)));
      if (options.ideal_device) {
        sim::HardwareSettings ideal;
        ideal.seed = rooms.back().hardware.seed;
        rooms.back().hardware = ideal;
      } else if (options.unit_seed != 0) {
        rooms.back().hardware = sim::same_unit(unit_of(options.unit_seed), options.unit_seed, rooms.back().hardware);
      }
    }
  std::vector<RoomCase> cases(rooms.size());
  std::atomic<size_t> next{0}, done{0};
  std::mutex report;
  auto work = [&] {
    for (size_t i; (i = next++) < rooms.size();) {
      cases[i] = evaluate_room(rooms[i], settings, options.keep_clouds);
      const size_t finished = ++done;
      if (progress) {
        const std::lock_guard<std::mutex> lock(report);
        progress(finished, rooms.size());
      }
    }
  };
  const int threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work);
  for (auto& thread : pool) thread.join();
  return cases;
}

std::vector<SweepSummary> summarize(const std::vector<RoomCase>& cases) {
  std::vector<SweepSummary> summaries;
  std::vector<const RoomCase*> all;
  for (auto category : sim::room_categories()) {
    std::vector<const RoomCase*> of;
    for (const auto& c : cases)
      if (c.category == category) of.push_back(&c);
    if (!of.empty()) summaries.push_back(summary_of(sim::category_name(category), of));
  }
  for (const auto& c : cases) all.push_back(&c);
  summaries.push_back(summary_of("all", all));
  return summaries;
}

}  // namespace scanbus::room_evaluation
