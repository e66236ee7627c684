#include "caliper/vocabulary/sex.h"

#include <cctype>

#include "caliper/errors.h"

namespace caliper {

const char* to_string(Sex sex) {
  switch (sex) {
    case Sex::Female: return "female";
    case Sex::Male: return "male";
    case Sex::Neutral: return "neutral";
  }
  return "neutral";
}

Sex parse_sex(const std::string& text) {
  std::string t;
  for (char c : text) t += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "female" || t == "f" || t == "woman") return Sex::Female;
  if (t == "male" || t == "m" || t == "man") return Sex::Male;
  if (t == "neutral" || t == "n") return Sex::Neutral;
  throw Error(ErrorKind::InvalidArgument, "sex must be female, male or neutral (got '" + text + "')", "sex");
}

}  // namespace caliper
