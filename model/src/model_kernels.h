#pragma once
// Registers model/kernels/*.cl with the engine's program cache (once per process). Every
// model op that launches its own kernels calls this first.
namespace simpli {
void ensureModelKernels();
} // namespace simpli
