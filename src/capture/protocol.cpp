// The capture protocol (paper §3.1 "The Virtual Caliper", §5): floor calibration from five taps
// (median), 1 s trigger holds with the tip kept still, ISAK repetitions (§3.1.3). Thresholds and
// their reasons: docs/capture.md.
#include "caliper/capture/protocol.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "caliper/errors.h"
#include "caliper/vocabulary/catalogue.h"

namespace caliper::capture {

namespace {

constexpr int kFloorTaps = 5;

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Component-wise median: robust to the odd tracking glitch in a hold, unlike the mean.
Eigen::Vector3d median_point(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d m;
  for (int k = 0; k < 3; ++k) {
    std::vector<double> c;
    c.reserve(pts.size());
    for (const auto& p : pts) c.push_back(p[k]);
    m[k] = median(std::move(c));
  }
  return m;
}

double max_distance(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& centre) {
  double d = 0;
  for (const auto& p : pts) d = std::max(d, (p - centre).norm());
  return d;
}

StepSpec step(const char* name, StepKind kind, const char* title, const char* self, const char* other) {
  return {name, kind, title, self, other, name};
}

std::vector<StepSpec> make_steps(bool all) {
  std::vector<StepSpec> s = {
      step("floor", StepKind::Floor, "Floor calibration",
           "Touch the floor with the tip of a controller and hold the trigger for one second. Do it at 5 different "
           "places around you.",
           "Touch the floor with the tip of a controller and hold the trigger for one second. Do it at 5 different "
           "places around the person."),
      step("stature", StepKind::Height, "Overall height",
           "Stand straight, look ahead, and place the tip of a controller on the top of your head. Hold the trigger "
           "for one second.",
           "Ask the person to stand straight and look ahead. Place the tip of a controller on the top of their head "
           "and hold the trigger for one second."),
      step("span", StepKind::Distance, "Arm span (fingers)",
           "Hold a controller in each hand with the tips at your fingertips and stretch your arms out to the sides "
           "as far as you can. Hold a trigger for one second.",
           "Ask the person to stretch their arms out to the sides. Put the controller tips at their two middle "
           "fingertips and hold a trigger for one second."),
      step("crotch_height", StepKind::Height, "Inseam height",
           "Stand with your feet slightly apart. Place the tip of a controller at your crotch, as high as is "
           "comfortable, and hold the trigger for one second.",
           "Ask the person to stand with feet slightly apart. Place the tip of a controller at their crotch and "
           "hold the trigger for one second."),
      step("hip_breadth", StepKind::Distance, "Hip width",
           "Place the controller tips on the widest points of your hips, one on each side, and hold a trigger for "
           "one second.",
           "Place the controller tips on the widest points of the person's hips, one on each side, and hold a "
           "trigger for one second."),
      step("arm_length", StepKind::Distance, "Arm length",
           "Let one arm hang. With the other hand place one tip on the top of that shoulder (the bony corner) and "
           "the other tip at the wrist bone. Hold a trigger for one second.",
           "Ask the person to let one arm hang. Place one tip on the top of that shoulder (the bony corner) and the "
           "other at the wrist bone. Hold a trigger for one second."),
  };
  if (all) {
    const std::vector<StepSpec> more = {
        step("chest_height", StepKind::Height, "Nipple height",
             "Stand straight and place the tip of a controller on your nipple (bust point). Hold the trigger for "
             "one second.",
             "Place the tip of a controller on the person's nipple (bust point) and hold the trigger for one second."),
        step("waist_height", StepKind::Height, "Navel height",
             "Stand straight and place the tip of a controller on your navel. Hold the trigger for one second.",
             "Place the tip of a controller on the person's navel and hold the trigger for one second."),
        step("biacromial_breadth", StepKind::Distance, "Shoulder width",
             "Place the controller tips on the bony tops of your two shoulders and hold a trigger for one second.",
             "Place the controller tips on the bony tops of the person's two shoulders and hold a trigger for one "
             "second."),
        step("chest_breadth", StepKind::Distance, "Chest width",
             "At nipple height, place the controller tips on the sides of your chest and hold a trigger for one "
             "second.",
             "At nipple height, place the controller tips on the sides of the person's chest and hold a trigger for "
             "one second."),
        step("waist_breadth", StepKind::Distance, "Waist width",
             "At navel height, place the controller tips on the sides of your waist and hold a trigger for one "
             "second.",
             "At navel height, place the controller tips on the sides of the person's waist and hold a trigger for "
             "one second."),
        step("waist_depth", StepKind::Distance, "Torso depth",
             "At navel height, place one tip on your navel and the other on your back, straight behind it. Hold a "
             "trigger for one second.",
             "At navel height, place one tip on the person's navel and the other on their back, straight behind it. "
             "Hold a trigger for one second."),
        step("wrist_span", StepKind::Distance, "Arm span (wrists)",
             "Stretch your arms out to the sides with the controller tips at your wrist bones. Hold a trigger for "
             "one second.",
             "Ask the person to stretch their arms out to the sides. Put the controller tips at their wrist bones and "
             "hold a trigger for one second."),
        step("forearm_length", StepKind::Distance, "Forearm length",
             "Bend one arm. Place one tip in the inner elbow and the other at the wrist bone of the same arm. Hold a "
             "trigger for one second.",
             "Ask the person to bend one arm. Place one tip in the inner elbow and the other at the wrist bone. Hold a "
             "trigger for one second."),
    };
    s.insert(s.end(), more.begin(), more.end());
  }
  return s;
}

}  // namespace

const char* to_string(Hand hand) { return hand == Hand::Left ? "left" : "right"; }
const char* to_string(Mode mode) { return mode == Mode::Self ? "self" : "other"; }
const char* to_string(StepSet set) { return set == StepSet::Core ? "core" : "all"; }
const char* to_string(StepKind kind) {
  switch (kind) {
    case StepKind::Floor: return "floor";
    case StepKind::Height: return "height";
    case StepKind::Distance: return "distance";
  }
  return "height";
}
const char* to_string(SessionState state) {
  switch (state) {
    case SessionState::Floor: return "floor";
    case SessionState::Measuring: return "measuring";
    case SessionState::Entries: return "entries";
    case SessionState::Done: return "done";
  }
  return "floor";
}
const char* to_string(EventType type) {
  switch (type) {
    case EventType::PointAccepted: return "point_accepted";
    case EventType::PointRejected: return "point_rejected";
    case EventType::StepDone: return "step_done";
    case EventType::SessionDone: return "session_done";
  }
  return "point_rejected";
}

Hand parse_hand(const std::string& text, const std::string& field) {
  if (text == "left") return Hand::Left;
  if (text == "right") return Hand::Right;
  throw Error(ErrorKind::InvalidArgument, field + " must be \"left\" or \"right\" (got \"" + text + "\")", field);
}
Mode parse_mode(const std::string& text, const std::string& field) {
  if (text == "self") return Mode::Self;
  if (text == "other") return Mode::Other;
  throw Error(ErrorKind::InvalidArgument, field + " must be \"self\" or \"other\" (got \"" + text + "\")", field);
}
StepSet parse_step_set(const std::string& text, const std::string& field) {
  if (text == "core") return StepSet::Core;
  if (text == "all") return StepSet::All;
  throw Error(ErrorKind::InvalidArgument, field + " must be \"core\" or \"all\" (got \"" + text + "\")", field);
}

const std::vector<StepSpec>& capture_steps(StepSet set) {
  static const std::vector<StepSpec> core = make_steps(false), all = make_steps(true);
  return set == StepSet::Core ? core : all;
}

void validate_samples(const std::vector<ControllerSample>& samples) {
  if (samples.size() > kMaxSamplesPerBatch)
    throw Error(ErrorKind::InvalidArgument,
                "a batch holds at most " + std::to_string(kMaxSamplesPerBatch) + " samples (got " +
                    std::to_string(samples.size()) + "); send batches about every 100 ms",
                "samples");
  for (size_t i = 0; i < samples.size(); ++i) {
    const ControllerSample& s = samples[i];
    const std::string at = "samples[" + std::to_string(i) + "]";
    if (!std::isfinite(s.t)) throw Error(ErrorKind::InvalidArgument, at + ".t must be a finite number of seconds", at + ".t");
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(s.position[k]) || std::abs(s.position[k]) > kMaxCoordinate)
        throw Error(ErrorKind::InvalidArgument, at + ".position[" + std::to_string(k) + "] must be a finite number of metres in [-100, 100]",
                    at + ".position");
    for (int k = 0; k < 4; ++k)
      if (!std::isfinite(s.orientation[k]))
        throw Error(ErrorKind::InvalidArgument, at + ".orientation[" + std::to_string(k) + "] must be a finite number", at + ".orientation");
    const double n = s.orientation.norm();
    if (std::abs(n - 1.0) > 0.05)
      throw Error(ErrorKind::InvalidArgument, at + ".orientation must be a unit quaternion [x, y, z, w] (norm " + fmt("%.3g", n) + ")",
                  at + ".orientation");
    if (!std::isfinite(s.trigger) || s.trigger < 0 || s.trigger > 1)
      throw Error(ErrorKind::InvalidArgument, at + ".trigger must be a number in [0, 1]", at + ".trigger");
  }
}

CaptureProtocol::CaptureProtocol(Config config) : config_(config), steps_(&capture_steps(config.steps)) { replay(); }

const StepSpec* CaptureProtocol::step_spec() const {
  return step_index_ < steps_->size() ? &(*steps_)[step_index_] : nullptr;
}

void CaptureProtocol::replay() {
  step_index_ = 0;
  floor_taps_.clear();
  floor_m_.reset();
  values_.clear();
  MeasuredValue current;
  for (size_t i = 0; i < points_.size(); ++i) {
    const CapturePoint& p = points_[i];
    const StepSpec* spec = step_spec();
    if (!spec || p.step != spec->name)
      throw Error(ErrorKind::Format,
                  "stored point " + std::to_string(i + 1) + " is for step '" + p.step + "' but the protocol expects '" +
                      (spec ? spec->name : std::string("nothing (all steps are done)")) + "'",
                  "points");
    if (!std::isfinite(p.value_m)) throw Error(ErrorKind::Format, "stored point " + std::to_string(i + 1) + " has no value", "points");
    if (spec->kind == StepKind::Floor) {
      floor_taps_.push_back(p.value_m);
      if (static_cast<int>(floor_taps_.size()) == kFloorTaps) {
        floor_m_ = median(floor_taps_);
        ++step_index_;
      }
      continue;
    }
    if (values_.empty() || values_.back().name != spec->name) values_.push_back({spec->name, {}, {}, IsakRule::NeedThird});
    MeasuredValue& v = values_.back();
    v.repetitions_m.push_back(p.value_m);
    if (v.repetitions_m.size() >= 2) {
      const IsakResult r = isak_combine(v.repetitions_m);
      v.rule = r.rule;
      v.value_m = r.value;
      if (r.value) ++step_index_;
    }
  }
}

SessionState CaptureProtocol::state() const {
  const StepSpec* spec = step_spec();
  if (spec) return spec->kind == StepKind::Floor ? SessionState::Floor : SessionState::Measuring;
  return sex_ && weight_kg_ ? SessionState::Done : SessionState::Entries;
}

std::optional<StepStatus> CaptureProtocol::current_step() const {
  const StepSpec* spec = step_spec();
  if (!spec) return std::nullopt;
  StepStatus s;
  s.spec = *spec;
  s.instruction = config_.mode == Mode::Self ? spec->instruction_self : spec->instruction_other;
  if (spec->kind == StepKind::Floor) {
    s.points_needed = kFloorTaps;
    s.points_done = static_cast<int>(floor_taps_.size());
    return s;
  }
  size_t reps = 0;
  if (!values_.empty() && values_.back().name == spec->name) reps = values_.back().repetitions_m.size();
  s.repetition = static_cast<int>(reps) + 1;
  s.repetitions_needed = reps >= 2 ? 3 : 2;  // a third only when the first two disagree
  return s;
}

int CaptureProtocol::steps_done() const { return static_cast<int>(step_index_); }
int CaptureProtocol::steps_total() const { return static_cast<int>(steps_->size()); }

std::map<std::string, double> CaptureProtocol::measurement_set() const {
  std::map<std::string, double> out;
  for (const auto& v : values_)
    if (v.value_m) out[v.name] = *v.value_m * 100.0;
  if (weight_kg_) out["weight"] = *weight_kg_;
  return out;
}

void CaptureProtocol::set_weight_kg(double kg) {
  const MeasurementInfo* info = find_measurement_info("weight");
  edge_to_si(*info, kg);  // throws naming "weight" and the accepted range
  weight_kg_ = kg;
}

void CaptureProtocol::set_sex(Sex sex) {
  if (sex == Sex::Neutral) throw Error(ErrorKind::InvalidArgument, "sex must be \"female\" or \"male\"", "sex");
  sex_ = sex;
}

bool CaptureProtocol::undo() {
  if (points_.empty()) return false;
  redo_.push_back(points_.back());
  points_.pop_back();
  replay();
  reset_live();
  return true;
}

bool CaptureProtocol::redo() {
  if (redo_.empty()) return false;
  points_.push_back(redo_.back());
  redo_.pop_back();
  try {
    replay();
  } catch (const Error&) {  // cannot happen for a point undone from here; keep the state sane
    redo_.push_back(points_.back());
    points_.pop_back();
    replay();
    return false;
  }
  reset_live();
  return true;
}

void CaptureProtocol::restore(std::vector<CapturePoint> points, std::vector<CapturePoint> redo) {
  std::vector<CapturePoint> old = std::move(points_);
  points_ = std::move(points);
  try {
    replay();
  } catch (...) {
    points_ = std::move(old);
    replay();
    throw;
  }
  redo_ = std::move(redo);
  reset_live();
}

void CaptureProtocol::reset_live() {
  hold_.reset();
  for (auto& h : hands_) {
    h.wait_release = h.pressed;  // a trigger still down must be released before the next point
  }
}

void CaptureProtocol::reject(const std::string& reason, std::vector<CaptureEvent>& events) const {
  CaptureEvent e;
  e.type = EventType::PointRejected;
  e.step = step_spec() ? step_spec()->name : "";
  e.reason = reason;
  events.push_back(std::move(e));
}

void CaptureProtocol::finish_hold(const Hold& hold, std::vector<CaptureEvent>& events) {
  const StepSpec* spec = step_spec();
  if (!spec) return;
  const HoldOptions& o = config_.hold;
  if (static_cast<int>(hold.tips.size()) < o.min_samples) {
    reject("only " + std::to_string(hold.tips.size()) + " tracked samples during the hold; hold again in view of the headset",
           events);
    return;
  }
  const Eigen::Vector3d tip = median_point(hold.tips);
  const double moved = max_distance(hold.tips, tip);
  if (moved > o.max_movement_m) {
    reject("the tip moved " + fmt("%.1f", moved * 100) + " cm while held; keep still", events);
    return;
  }
  CapturePoint p;
  p.step = spec->name;
  p.hand = hold.hand;
  p.tip = tip;
  p.other_tip = tip;
  p.t_start = hold.t_start;
  p.t_end = hold.t_last;
  switch (spec->kind) {
    case StepKind::Floor:
      p.value_m = tip.y();
      p.repetition = static_cast<int>(floor_taps_.size()) + 1;
      break;
    case StepKind::Height:
      p.value_m = tip.y() - floor_m_.value_or(0.0);
      break;
    case StepKind::Distance: {
      if (static_cast<int>(hold.other_tips.size()) < o.min_samples) {
        reject(std::string("the other controller (") + to_string(hold.hand == Hand::Left ? Hand::Right : Hand::Left) +
                   ") was not tracked during the hold; keep both in view",
               events);
        return;
      }
      const Eigen::Vector3d other = median_point(hold.other_tips);
      const double other_moved = max_distance(hold.other_tips, other);
      if (other_moved > o.max_movement_m) {
        reject("the other tip moved " + fmt("%.1f", other_moved * 100) + " cm while held; keep both still", events);
        return;
      }
      p.other_tip = other;
      p.value_m = (tip - other).norm();
      break;
    }
  }
  if (spec->kind != StepKind::Floor) {
    const auto cur = current_step();
    p.repetition = cur ? cur->repetition : 1;
    // Values no person can have are tracking or aiming mistakes, not measurements.
    const MeasurementInfo* info = find_measurement_info(spec->name);
    if (info && (p.value_m * 100 < info->min_edge || p.value_m * 100 > info->max_edge)) {
      reject(fmt("%.1f", p.value_m * 100) + " cm is outside the accepted range of " + spec->name + " (" +
                 fmt("%g", info->min_edge) + "–" + fmt("%g", info->max_edge) + " cm); check the tip placement",
             events);
      return;
    }
  } else if (std::abs(p.value_m) > 0.5) {
    reject("the tip is " + fmt("%.0f", p.value_m * 100) + " cm from the floor the headset knows; touch the floor", events);
    return;
  }
  const std::size_t before = step_index_;
  points_.push_back(p);
  redo_.clear();
  replay();
  CaptureEvent accepted;
  accepted.type = EventType::PointAccepted;
  accepted.step = p.step;
  accepted.value_cm = p.value_m * 100;
  accepted.point = p;
  events.push_back(std::move(accepted));
  if (step_index_ != before) {
    CaptureEvent done;
    done.type = EventType::StepDone;
    done.step = p.step;
    if (spec->kind == StepKind::Floor) done.value_cm = floor_m_.value_or(0) * 100;
    else if (!values_.empty() && values_.back().value_m) done.value_cm = *values_.back().value_m * 100;
    events.push_back(std::move(done));
    if (!step_spec()) {
      CaptureEvent all;
      all.type = EventType::SessionDone;
      all.step = p.step;
      events.push_back(std::move(all));
    }
  }
}

std::vector<CaptureEvent> CaptureProtocol::feed(const std::vector<ControllerSample>& samples, const Eigen::Vector3d& tip_offset) {
  validate_samples(samples);
  if (!tip_offset.allFinite()) throw Error(ErrorKind::InvalidArgument, "the tip offset must be finite", "profile");
  std::vector<const ControllerSample*> order;
  order.reserve(samples.size());
  for (const auto& s : samples) order.push_back(&s);
  std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) { return a->t < b->t; });

  std::vector<CaptureEvent> events;
  const HoldOptions& o = config_.hold;
  for (const ControllerSample* s : order) {
    HandState& hs = hands_[s->hand == Hand::Left ? 0 : 1];
    if (hs.seen && s->t <= hs.last_t) {
      if (hs.last_t - s->t > o.clock_reset_s) {
        // The page restarted its clock (reload, new tab): forget live state, keep the points.
        hold_.reset();
        for (auto& h : hands_) h = HandState{};
      } else {
        ++ignored_;  // duplicate or out of order
        continue;
      }
    }
    hs.seen = true;
    hs.last_t = s->t;
    const Eigen::Quaterniond q(s->orientation[3], s->orientation[0], s->orientation[1], s->orientation[2]);
    const Eigen::Vector3d tip = s->position + q.normalized() * tip_offset;
    const bool pressed = hs.pressed ? s->trigger > o.release_threshold : s->trigger >= o.press_threshold;
    const bool rising = pressed && !hs.pressed;
    hs.pressed = pressed;
    if (!pressed) hs.wait_release = false;
    if (!step_spec()) continue;  // nothing left to measure: only follow the triggers

    if (hold_ && hold_->hand == s->hand) {
      const double gap = s->t - hold_->t_last;
      if (gap > o.max_gap_s) {
        hold_.reset();
        hs.wait_release = pressed;
        reject("tracking stopped for " + fmt("%.1f", gap) + " s during the hold; hold again", events);
      } else if (!pressed) {
        const double held = s->t - hold_->t_start;
        hold_.reset();
        reject("held " + fmt("%.1f", held) + " s; hold the trigger for " + fmt("%g", o.hold_seconds) + " s", events);
      } else {
        hold_->tips.push_back(tip);
        hold_->t_last = s->t;
        if (s->t - hold_->t_start >= o.hold_seconds) {
          const Hold done = std::move(*hold_);
          hold_.reset();
          hs.wait_release = true;
          finish_hold(done, events);
        }
      }
      continue;
    }
    if (hold_) {  // the other controller during a hold
      if (s->t >= hold_->t_start && s->t - hold_->t_last <= o.max_gap_s) hold_->other_tips.push_back(tip);
      continue;
    }
    if (rising && !hs.wait_release) {
      hold_ = Hold{s->hand, s->t, s->t, {tip}, {}};
    }
  }
  return events;
}

}  // namespace caliper::capture
