// A deliberately bad capture header (tests/CMakeLists.txt, layering_*): capture may include
// protocol, measure and the vocabulary, never body.
#pragma once
#include "caliper/errors.h"
#include "caliper/protocol/isak.h"
#include "caliper/vocabulary/sex.h"
#include "caliper/body/body_model.h"
