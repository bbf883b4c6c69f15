#pragma once
// --reference-margin of `simpli infer` (one value) and `simpli eval` (one per network): the
// reference camera widened by this fraction of the image on every side (scene::widenedCamera).
namespace CLI {
class App;
}

namespace simpli::app {

/// The option's help text that infer and eval share (eval adds how to give one per network).
extern const char* const kReferenceMarginHelp;

/// --reference-margin F with its default shown (infer).
void addReferenceMarginOption(CLI::App& cmd, double& margin);

/// Throws simpli::Error naming the flag and value unless 0 <= margin <= the widest margin.
void checkReferenceMargin(double margin);

} // namespace simpli::app
