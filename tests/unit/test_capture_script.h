// A scripted person for the capture tests: known landmarks in the headset's local-floor space,
// two controllers whose grip poses are generated frame by frame (72 Hz) with the tip placed on a
// landmark, tracking jitter, and the trigger held or tapped. The expected measurement of every
// step is computed from the landmarks by hand, not by the code under test.
#pragma once
#include <Eigen/Geometry>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "caliper/capture/protocol.h"
#include "caliper/capture/service.h"

namespace caliper::test {

// A capture service's options with only its database file set.
inline capture::CaptureServiceOptions service_options(const std::string& database) {
  capture::CaptureServiceOptions o;
  o.database = database;
  return o;
}

using capture::ControllerSample;
using capture::Hand;

struct ScriptedPerson {
  double floor = 0.012;  // where the real floor is in local-floor (tracking offset, paper §5)
  // Landmarks, metres, real floor at y = floor. A 172 cm person facing +Z.
  Eigen::Vector3d head_top{0.02, 1.72 + 0.012, 0.05};
  Eigen::Vector3d left_fingertip{0.86, 1.42, 0.0}, right_fingertip{-0.84, 1.41, 0.02};
  Eigen::Vector3d crotch{0.0, 0.80 + 0.012, 0.03};
  Eigen::Vector3d hip_left{0.18, 0.90, 0.0}, hip_right{-0.17, 0.91, 0.01};
  Eigen::Vector3d acromion{0.20, 1.43, 0.0}, wrist{0.24, 0.85, 0.05};

  double stature() const { return head_top.y() - floor; }
  double span() const { return (left_fingertip - right_fingertip).norm(); }
  double crotch_height() const { return crotch.y() - floor; }
  double hip_breadth() const { return (hip_left - hip_right).norm(); }
  double arm_length() const { return (acromion - wrist).norm(); }
};

class SampleScript {
 public:
  explicit SampleScript(Eigen::Vector3d tip_offset, unsigned seed = 7, double jitter_m = 0.001)
      : offset_(tip_offset), rng_(seed), jitter_(jitter_m) {
    // Controllers held tilted, so the tip offset matters: rotated 30° about X and ±20° about Y.
    orient_[0] = (Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.52, Eigen::Vector3d::UnitX())).toRotationMatrix();
    orient_[1] = (Eigen::AngleAxisd(-0.35, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(0.52, Eigen::Vector3d::UnitX())).toRotationMatrix();
  }

  double dt = 1.0 / 72.0;
  double t = 10.0;
  Eigen::Vector3d tip[2] = {Eigen::Vector3d(0.3, 1.0, 0.3), Eigen::Vector3d(-0.3, 1.0, 0.3)};
  double trigger[2] = {0, 0};
  bool tracked[2] = {true, true};
  bool swap_labels = false;   // the page mixes up left and right
  Eigen::Vector3d drift[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};  // m/s while running

  // Emits `seconds` of frames (both controllers each frame).
  void run(double seconds) {
    const int n = static_cast<int>(std::lround(seconds / dt));
    std::uniform_real_distribution<double> u(-jitter_, jitter_);
    for (int i = 0; i < n; ++i) {
      t += dt;
      for (int h = 0; h < 2; ++h) {
        tip[h] += drift[h] * dt;
        if (!tracked[h]) continue;
        ControllerSample s;
        s.t = t;
        s.hand = (h == 0) != swap_labels ? Hand::Left : Hand::Right;
        const Eigen::Vector3d noise(u(rng_), u(rng_), u(rng_));
        s.position = tip[h] - orient_[h] * offset_ + noise;
        const Eigen::Quaterniond q(orient_[h]);
        s.orientation = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
        s.trigger = trigger[h];
        samples.push_back(s);
      }
    }
  }

  // Places the tips, rests, holds hand `h`'s trigger for `seconds`, releases and rests.
  void hold(int h, const Eigen::Vector3d& tip_h, double seconds, const Eigen::Vector3d* other = nullptr) {
    tip[h] = tip_h;
    if (other) tip[1 - h] = *other;
    run(0.3);
    trigger[h] = 1.0;
    run(seconds);
    trigger[h] = 0.0;
    run(0.3);
  }

  // Moves the collected samples out, in batches of ~100 ms, in order.
  std::vector<std::vector<ControllerSample>> batches(double batch_seconds = 0.1) {
    std::vector<std::vector<ControllerSample>> out;
    std::vector<ControllerSample> cur;
    double start = samples.empty() ? 0 : samples.front().t;
    for (const auto& s : samples) {
      if (s.t - start >= batch_seconds && !cur.empty()) {
        out.push_back(std::move(cur));
        cur.clear();
        start = s.t;
      }
      cur.push_back(s);
    }
    if (!cur.empty()) out.push_back(std::move(cur));
    samples.clear();
    return out;
  }

  std::vector<ControllerSample> samples;
  Eigen::Matrix3d orient_[2];

 private:
  Eigen::Vector3d offset_;
  std::mt19937 rng_;
  double jitter_;
};

// Floor taps at five places (the real floor, ±2 mm of unevenness).
inline void script_floor(SampleScript& s, const ScriptedPerson& p, int hand = 1) {
  const double dy[5] = {0.001, -0.002, 0.0, 0.002, -0.001};
  for (int i = 0; i < 5; ++i) s.hold(hand, Eigen::Vector3d(0.3 * std::cos(i * 1.2), p.floor + dy[i], 0.3 * std::sin(i * 1.2)), 1.2);
}

// The five core steps, each twice (consistent repetitions).
inline void script_core(SampleScript& s, const ScriptedPerson& p) {
  for (int rep = 0; rep < 2; ++rep) s.hold(1, p.head_top, 1.2);
  for (int rep = 0; rep < 2; ++rep) s.hold(0, p.left_fingertip, 1.2, &p.right_fingertip);
  for (int rep = 0; rep < 2; ++rep) s.hold(1, p.crotch, 1.2);
  for (int rep = 0; rep < 2; ++rep) s.hold(1, p.hip_right, 1.2, &p.hip_left);
  for (int rep = 0; rep < 2; ++rep) s.hold(0, p.wrist, 1.2, &p.acromion);
}

}  // namespace caliper::test
