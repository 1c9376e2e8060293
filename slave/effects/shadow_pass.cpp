// PLACEHOLDER until the soft-shadow pass lands (being written now); it refuses with a message.
#include <stdexcept>
#include "slave/effects/pipeline.h"
namespace glcast::slave::effects {
std::unique_ptr<Pass> make_shadow_pass(const GlApi&, const EffectParams&) { throw std::runtime_error("shadows: not yet"); }
std::vector<ParamSpec> shadow_param_specs() { return {}; }
}
