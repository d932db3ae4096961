// TEMPORARY skeleton stub: replaced by scene validation.
#include "scene/validate.h"

namespace radbake {
bool validateScene(Scene&, Diagnostics& diagnostics) { return !diagnostics.hasErrors(); }
}  // namespace radbake
