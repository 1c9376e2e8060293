// PLACEHOLDER until the precipitation pass lands; it refuses with a message.
#include <stdexcept>
#include "slave/effects/pipeline.h"
namespace glcast::slave::effects {
std::unique_ptr<Pass> make_precipitation_pass(const GlApi&, const EffectParams&, bool) { throw std::runtime_error("snow: not yet"); }
std::vector<ParamSpec> precipitation_param_specs() { return {}; }
}
