// The sex a body model, a measurement set or a capture session is for.
#pragma once
#include <string>

namespace caliper {

enum class Sex { Female, Male, Neutral };
const char* to_string(Sex sex);
Sex parse_sex(const std::string& text);  // "female"|"male"|"neutral" (also f/m/n); throws Error

}  // namespace caliper
