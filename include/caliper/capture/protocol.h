// The Virtual Caliper's capture protocol (paper §3.1, §5) as a state machine fed with
// timestamped controller samples. Floor calibration first (5 taps, floor = median tip height),
// then each measurement step repeated per ISAK (protocol/isak.h). A point is taken when a trigger
// is held for 1 s while the tip stays still; its value is the median over the hold.
// No I/O: storage (store.h) and sessions with pairing (service.h) are built on top of it.
#pragma once
#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "caliper/protocol/isak.h"
#include "caliper/vocabulary/sex.h"

namespace caliper::capture {

enum class Hand { Left, Right };
enum class Mode { Self, Other };      // who holds the controllers: the person, or a measurer
enum class StepSet { Core, All };     // the paper's 5 selected measurements, or all 13
enum class StepKind { Floor, Height, Distance };
enum class SessionState { Floor, Measuring, Entries, Done };

const char* to_string(Hand hand);
const char* to_string(Mode mode);
const char* to_string(StepSet set);
const char* to_string(StepKind kind);
const char* to_string(SessionState state);
// Parse the strings above; throw Error(InvalidArgument) naming `field`.
Hand parse_hand(const std::string& text, const std::string& field = "hand");
Mode parse_mode(const std::string& text, const std::string& field = "mode");
StepSet parse_step_set(const std::string& text, const std::string& field = "steps");

// One controller's grip pose at one moment, as WebXR's gripSpace gives it in `local-floor`.
struct ControllerSample {
  double t = 0;                                              // seconds, any monotonic origin
  Hand hand = Hand::Right;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();        // metres, +Y up
  Eigen::Vector4d orientation = Eigen::Vector4d(0, 0, 0, 1);  // quaternion x, y, z, w
  double trigger = 0;                                        // 0 (released) … 1 (pressed)
};

// Limits a sample batch must respect (validate_samples).
constexpr std::size_t kMaxSamplesPerBatch = 4096;  // ~10 s of two controllers at 120 Hz
constexpr double kMaxCoordinate = 100.0;           // metres from the origin of local-floor

// Throws Error(InvalidArgument) naming the first bad field, e.g. "samples[3].position":
// non-finite numbers, |coordinate| > 100 m, a quaternion far from unit length, trigger outside
// [0, 1], too many samples.
void validate_samples(const std::vector<ControllerSample>& samples);

struct StepSpec {
  std::string name;          // "floor" or a canonical measurement name ("stature", …)
  StepKind kind = StepKind::Height;
  std::string title;         // "Overall height"
  std::string instruction_self, instruction_other;
  std::string illustration;  // an id the page draws ("stature")
};
// "floor" first, then the paper's 5 selected measurements; StepSet::All adds the other 8.
const std::vector<StepSpec>& capture_steps(StepSet set);

// Hold detection. Defaults and why: docs/capture.md "Thresholds".
struct HoldOptions {
  double hold_seconds = 1.0;       // paper §3.1: the trigger is held for one second
  double press_threshold = 0.7;    // trigger value that starts a press …
  double release_threshold = 0.3;  // … and the value under which it is released (hysteresis)
  double max_movement_m = 0.01;    // largest distance of a tip from its median over the hold
  double max_gap_s = 0.3;          // longer gaps between a held controller's samples void the hold
  int min_samples = 5;             // fewer samples of a hold cannot give a robust median
  double clock_reset_s = 5.0;      // t going back more than this: a new clock (page reloaded)
};

// An accepted point: what storage keeps and what replays a session.
struct CapturePoint {
  std::string step;            // step name
  int repetition = 1;          // 1-based; for "floor", the tap number
  double value_m = 0;          // floor: tip height; height: above the floor; distance: tip to tip
  Hand hand = Hand::Right;     // the controller whose trigger was held
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();        // median tip of that controller, metres
  Eigen::Vector3d other_tip = Eigen::Vector3d::Zero();  // the other tip (distance steps; else = tip)
  double t_start = 0, t_end = 0;                        // the hold, in the sample clock
};

enum class EventType { PointAccepted, PointRejected, StepDone, SessionDone };
const char* to_string(EventType type);

struct CaptureEvent {
  EventType type = EventType::PointAccepted;
  std::string step;
  std::optional<double> value_cm;  // accepted point or finished step
  std::string reason;              // why a point was rejected
  std::optional<CapturePoint> point;  // the accepted point (PointAccepted)
};

struct StepStatus {
  StepSpec spec;
  std::string instruction;  // for the session's mode
  int repetition = 1;       // the repetition being taken (1-based)
  int repetitions_needed = 1;
  int points_needed = 1;    // floor: 5 taps; measurement steps: 1 point per repetition
  int points_done = 0;
};

struct MeasuredValue {
  std::string name;
  std::vector<double> repetitions_m;
  std::optional<double> value_m;  // once ISAK has settled
  IsakRule rule = IsakRule::NeedThird;
};

class CaptureProtocol {
 public:
  struct Config {
    Mode mode = Mode::Self;
    StepSet steps = StepSet::Core;
    HoldOptions hold;
  };
  explicit CaptureProtocol(Config config);

  // Feeds a batch (validated first: throws before changing anything). Samples are taken in time
  // order; per controller, a sample not later than the previous one is ignored (duplicate or
  // out of order) unless t went back by more than clock_reset_s (a new clock: live holds reset).
  // `tip_offset` is the profile's tip in grip space. Returns what happened, in order.
  std::vector<CaptureEvent> feed(const std::vector<ControllerSample>& samples, const Eigen::Vector3d& tip_offset);
  std::size_t ignored_samples() const { return ignored_; }

  // Undo removes the last accepted point (a floor tap or a repetition); redo puts it back.
  // A new accepted point clears the redo list. Both return false when there is nothing to do.
  bool undo();
  bool redo();

  // Rebuilds the state from stored points (in order) and the redo list (next to redo last).
  // Throws Error(Format) when the points do not follow the protocol.
  void restore(std::vector<CapturePoint> points, std::vector<CapturePoint> redo);

  void set_weight_kg(double kg);  // checked against the catalogue (Error naming "weight")
  void set_sex(Sex sex);          // female or male (neutral: Error naming "sex")

  const Config& config() const { return config_; }
  SessionState state() const;
  std::optional<StepStatus> current_step() const;
  int steps_done() const;   // the floor counts as a step
  int steps_total() const;
  std::optional<double> floor_m() const { return floor_m_; }
  const std::vector<MeasuredValue>& values() const { return values_; }
  std::optional<Sex> sex() const { return sex_; }
  std::optional<double> weight_kg() const { return weight_kg_; }
  const std::vector<CapturePoint>& points() const { return points_; }
  const std::vector<CapturePoint>& redo_points() const { return redo_; }
  // Settled values in cm and the weight in kg, by canonical name: the measurement set.
  std::map<std::string, double> measurement_set() const;

 private:
  struct HandState {
    bool seen = false;
    double last_t = 0;
    bool pressed = false;
    bool wait_release = false;  // a hold ended (accepted or rejected) while still pressed
  };
  struct Hold {
    Hand hand = Hand::Right;
    double t_start = 0, t_last = 0;
    std::vector<Eigen::Vector3d> tips, other_tips;
  };

  void replay();  // recomputes the derived state from points_
  void reset_live();
  void finish_hold(const Hold& hold, std::vector<CaptureEvent>& events);
  void reject(const std::string& reason, std::vector<CaptureEvent>& events) const;
  const StepSpec* step_spec() const;  // the current step, nullptr when all are done

  Config config_;
  const std::vector<StepSpec>* steps_;
  std::vector<CapturePoint> points_, redo_;
  std::optional<Sex> sex_;
  std::optional<double> weight_kg_;
  // Derived by replay().
  std::size_t step_index_ = 0;
  std::vector<double> floor_taps_;
  std::optional<double> floor_m_;
  std::vector<MeasuredValue> values_;
  // Live (not stored: a hold in progress is lost with the process, by design).
  HandState hands_[2];
  std::optional<Hold> hold_;
  std::size_t ignored_ = 0;
};

}  // namespace caliper::capture
