// Input mistakes a person makes when typing measurements: height and weight swapped,
// a height in metres, millimetres or inches, a weight in pounds, a length in inches, millimetres
// or metres. Each suspect value comes with what was probably meant, so a tool can ask "did you
// mean …?" instead of building a wrong avatar or refusing with a bare range. Judged on values as
// typed, in the user's units (cm, kg), before range checks; limits are far outside adult people
// (no subject of the ANSUR II development data is flagged: tests/unit/test_input_check.cpp).
#pragma once
#include <map>
#include <string>
#include <vector>

#include "caliper/errors.h"

namespace caliper {

struct SuspectValue {
  std::string field;        // canonical measurement name
  double given = 0;         // as typed, cm or kg
  double suggested = 0;     // what it probably meant, cm or kg
  std::string reason;       // plain words, e.g. "weight 165 kg at height 165 cm looks like pounds"
};

// `edge_values`: canonical name → value in cm or kg as typed. Returns the suspects, height and
// weight first; empty when nothing looks mistaken.
std::vector<SuspectValue> suspect_input_mistakes(const std::map<std::string, double>& edge_values);

// The values with every suggestion applied (what "Use these" means).
std::map<std::string, double> apply_suggestions(std::map<std::string, double> edge_values,
                                                const std::vector<SuspectValue>& suspects);

// One message for all suspects: "height 60 cm and weight 165 kg look swapped: did you mean
// height 165 cm, weight 60 kg? …; repeat with --force (API: "force": true) to use them as given".
std::string describe_suspects(const std::vector<SuspectValue>& suspects);

// Thrown when values look like typing mistakes (kind InvalidArgument, field the first suspect's,
// message describe_suspects): its own type, so a tool can ask "did you mean …?" (the CLI's exit
// code 6, Python's SuspectInputError) instead of treating it as a bad value.
class SuspectInputError : public Error {
 public:
  explicit SuspectInputError(std::vector<SuspectValue> suspects);
  const std::vector<SuspectValue>& suspects() const noexcept { return suspects_; }

 private:
  std::vector<SuspectValue> suspects_;
};

}  // namespace caliper
