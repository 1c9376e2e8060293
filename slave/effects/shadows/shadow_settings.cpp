#include "slave/effects/shadows/shadow_settings.h"

#include <cmath>
#include <stdexcept>

#include "slave/effects/pipeline.h"

namespace glcast::slave::effects {

namespace {

struct MethodName {
    ShadowMethod method;
    const char* name;
};
const MethodName kMethods[] = {
    {ShadowMethod::ErosionPcf, "erosion-pcf"}, {ShadowMethod::ErosionDirect, "erosion-direct"},
    {ShadowMethod::Pcss8, "pcss-8"},           {ShadowMethod::Pcss32, "pcss-32"},
    {ShadowMethod::Pcss64, "pcss-64"},         {ShadowMethod::Reference, "reference"},
    {ShadowMethod::ScreenSpace, "screen-space"},
};

}  // namespace

const char* method_name(ShadowMethod method) {
    for (const MethodName& m : kMethods)
        if (m.method == method) return m.name;
    return "?";
}

bool parse_method(const std::string& name, ShadowMethod& method) {
    for (const MethodName& m : kMethods)
        if (name == m.name) {
            method = m.method;
            return true;
        }
    return false;
}

std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (const MethodName& m : kMethods) names.emplace_back(m.name);
    return names;
}

int pcss_blocker_samples(ShadowMethod method) {
    switch (method) {
    case ShadowMethod::Pcss8: return 8;
    case ShadowMethod::Pcss32: return 32;
    case ShadowMethod::Pcss64: return 64;
    default: return 0;
    }
}

std::vector<ParamSpec> shadow_param_specs() {
    ParamSpec method{"shadows.method", 0, 0, 0,
                     "erosion-pcf (default), erosion-direct, pcss-8, pcss-32, pcss-64, reference or screen-space", true};
    return {
        method,
        {"shadows.strength", 0.6, 0, 1, "darkening of a fully shadowed pixel facing the light: color *= 1 - strength * facing * (1 - visibility)"},
        {"shadows.use_program_light", 1, 0, 1, "1: the program's light when it has one (its first enabled fixed-function light, or a shader program's sun: docs/shadows.md); 0: always shadows.light_*"},
        {"shadows.light_x", 0.4, -1e6, 1e6, "light position or direction in the main view's eye space, x (used without a program light)"},
        {"shadows.light_y", 1.0, -1e6, 1e6, "light, eye-space y"},
        {"shadows.light_z", 0.5, -1e6, 1e6, "light, eye-space z"},
        {"shadows.light_w", 0, 0, 1, "0: (x, y, z) is the direction towards a directional light; 1: the position of a positional light"},
        {"shadows.light_size", 0.5, 0, 1e4, "diameter of a positional light's disk, in eye-space units (the program's world units unless its modelview scales)"},
        {"shadows.light_angle", 2.0, 0, 30, "angular diameter of a directional light's disk, degrees (the sun: 0.53)"},
        {"shadows.map_size", 2048, 256, 8192, "shadow map size, texels per side"},
        {"shadows.max_distance", 0, 0, 1e7, "the shadows reach this far into the main view, eye-space units; 0: 120 of its near-plane distances but at least 60, at most to its far plane"},
        {"shadows.max_light_fov", 150, 10, 170, "widest field of view of a positional light's perspective shadow map, degrees"},
        {"shadows.bias", 1.0, 0, 100, "depth bias of shadow comparisons, in shadow-map texel widths (world size at the receiver)"},
        {"shadows.offset_factor", 1.5, 0, 100, "glPolygonOffset factor while the shadow map is rendered"},
        {"shadows.offset_units", 2.0, 0, 1000, "glPolygonOffset units while the shadow map is rendered"},
        {"shadows.max_penumbra", 24, 1, 128, "largest penumbra half-width searched, pixels; also the guard band rendered around a tile"},
        {"shadows.pcf_samples", 32, 4, 256, "PCF samples of erosion-pcf and pcss-*"},
        {"shadows.reference_samples", 512, 1, 4096, "points on the area light averaged by the reference method"},
        {"shadows.silhouette_check", 1, 0, 1, "1: keep only hard-shadow edges that are silhouettes in the shadow map"},
        {"shadows.line_fit", 1, 0, 1, "1: erosion-direct measures distances to least-squares lines through the edge pixels"},
        {"shadows.direct_profile", 0, 0, 1, "erosion-direct's penumbra profile: 0 the method's linear ramp, 1 the occluded area of a round light"},
        {"shadows.screen_steps", 32, 4, 256, "screen-space shadows (every method's fallback for frames that cannot be re-rendered): depth samples along each pixel's ray towards the light"},
        {"shadows.screen_reach", 1.0, 0.01, 1, "screen-space shadows: longest ray on the screen, as a share of the tile's height"},
        {"shadows.screen_thickness", 0.08, 0.001, 10, "screen-space shadows: a depth sample hides points up to this share of its eye depth behind it"},
        {"shadows.rerender_depth", 1, 0, 1, "1: re-render the camera depth with a guard band around the tile (no seams on a wall); 0: use the window's depth buffer (one scene render less, no guard band)"},
    };
}

ShadowSettings shadow_settings_from(const EffectParams& params) {
    ShadowSettings s;
    const std::string method = params.text("shadows.method");
    if (!method.empty() && !parse_method(method, s.method)) {
        std::string known;
        for (const std::string& n : method_names()) known += " " + n;
        throw std::runtime_error("effect parameter shadows.method: unknown method \"" + method + "\" (known:" + known + ")");
    }
    s.strength = params.number("shadows.strength");
    s.use_program_light = params.flag("shadows.use_program_light");
    s.fallback_light = {params.number("shadows.light_x"), params.number("shadows.light_y"),
                        params.number("shadows.light_z"), params.number("shadows.light_w")};
    if (glm::length(glm::dvec3(s.fallback_light)) == 0)
        throw std::runtime_error("effect parameters shadows.light_x/y/z: the light vector is zero");
    s.light_size = params.number("shadows.light_size");
    s.light_angle_deg = params.number("shadows.light_angle");
    s.map_size = int(params.number("shadows.map_size"));
    s.max_distance = params.number("shadows.max_distance");
    s.max_light_fov_deg = params.number("shadows.max_light_fov");
    s.bias_texels = params.number("shadows.bias");
    s.offset_factor = params.number("shadows.offset_factor");
    s.offset_units = params.number("shadows.offset_units");
    s.max_penumbra_px = int(std::lround(params.number("shadows.max_penumbra")));
    s.pcf_samples = int(std::lround(params.number("shadows.pcf_samples")));
    s.reference_samples = int(std::lround(params.number("shadows.reference_samples")));
    s.silhouette_check = params.flag("shadows.silhouette_check");
    s.line_fit = params.flag("shadows.line_fit");
    s.rerender_depth = params.flag("shadows.rerender_depth");
    s.direct_disk_profile = params.flag("shadows.direct_profile");
    s.screen_steps = int(std::lround(params.number("shadows.screen_steps")));
    s.screen_reach = params.number("shadows.screen_reach");
    s.screen_thickness = params.number("shadows.screen_thickness");
    return s;
}

}  // namespace glcast::slave::effects
