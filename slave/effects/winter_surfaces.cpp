// PLACEHOLDER until the snow cover / icicle pass lands (being written now); it refuses with a message.
#include <stdexcept>
#include "slave/effects/pipeline.h"
namespace glcast::slave::effects {
std::unique_ptr<Pass> make_winter_surfaces_pass(const GlApi&, const EffectParams&, bool, bool) { throw std::runtime_error("cover: not yet"); }
std::vector<ParamSpec> winter_surfaces_param_specs() { return {}; }
}
