// --reference-margin of infer and eval (reference_margin_option.h).
#include "reference_margin_option.h"

#include "simpli/error.h"
#include "simpli/model/scene/reference_camera.h"

#include <CLI/CLI.hpp>

namespace simpli::app {

const char* const kReferenceMarginHelp =
    "Widen the reference camera (the MLI's frame) by this fraction of the image on every side, 0 "
    "to 0.5 (0 = the reference method): novel views off to the side then find layers where the "
    "sources' frame ends (flower: +0.8 dB at 0.06)";

void addReferenceMarginOption(CLI::App& cmd, double& margin) {
  cmd.add_option("--reference-margin", margin, kReferenceMarginHelp)->capture_default_str();
}

void checkReferenceMargin(double margin) {
  if (!(margin >= 0 && margin <= scene::maxReferenceMargin))
    fail("--reference-margin ", margin, ": must be between 0 and ", scene::maxReferenceMargin);
}

} // namespace simpli::app
