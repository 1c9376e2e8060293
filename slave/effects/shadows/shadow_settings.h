// Settings of the soft-shadow pass (docs/shadows.md), read once from the effect parameters
// ("shadows.*", declared by shadow_param_specs() in shadow_settings.cpp).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "slave/effects/effect_params.h"

namespace glcast::slave::effects {

// How the shadow factor of a pixel is computed (docs/shadows.md, "Methods").
enum class ShadowMethod {
    ErosionPcf,     // the erosion method's first solution: eroded edge regions, PCF scaled by the penumbra there
    ErosionDirect,  // its second: the shadow factor from the erosion distance, least-squares line corrected
    Pcss8,          // percentage-closer soft shadows with 8, 32 or 64 blocker-search samples
    Pcss32,
    Pcss64,
    Reference,      // the average of hard shadows from many points on the area light
    ScreenSpace,    // no shadow map: each pixel marches the camera depth towards the light
};

// "erosion-pcf", "erosion-direct", "pcss-8", "pcss-32", "pcss-64", "reference", "screen-space".
const char* method_name(ShadowMethod method);
// False for an unknown name.
bool parse_method(const std::string& name, ShadowMethod& method);
std::vector<std::string> method_names();
int pcss_blocker_samples(ShadowMethod method);  // 0 for the non-PCSS methods

struct ShadowSettings {
    ShadowMethod method = ShadowMethod::ErosionPcf;
    double strength = 0.6;        // 0: no darkening; 1: shadowed pixels become black

    bool use_program_light = true;         // FrameView::light when the program has one
    glm::dvec4 fallback_light{0.4, 1.0, 0.5, 0.0};  // main view's eye space; w = 0: directional
    double light_size = 0.5;      // diameter of a positional light's disk, eye-space units
    double light_angle_deg = 2.0; // angular diameter of a directional light, degrees

    int map_size = 2048;          // shadow map texels per side
    double max_distance = 0;      // the shadows reach this eye distance into the main view (0: shadow_reach's)
    double max_light_fov_deg = 150;  // widest perspective shadow map of a positional light
    double bias_texels = 1.0;     // depth bias of the comparisons, in shadow-map texels of world size
    double offset_factor = 1.5, offset_units = 2.0;  // glPolygonOffset while rendering the map

    int max_penumbra_px = 24;     // penumbra search radius bound = guard band, pixels
    int pcf_samples = 32;         // PCF samples (erosion/PCF and PCSS)
    int reference_samples = 512;  // light samples of the reference
    bool silhouette_check = true; // keep only hard-shadow edges that are silhouettes in the shadow map
    bool line_fit = true;         // least-squares line correction of erosion/direct
    bool direct_disk_profile = false;  // erosion/direct: a round light's profile instead of the method's ramp
    bool rerender_depth = true;   // camera depth re-rendered with a guard band (else the window's depth)

    // Screen-space marching: every method's fallback when the frame cannot be re-rendered.
    int screen_steps = 32;           // depth samples along each pixel's ray towards the light
    double screen_reach = 1.0;       // longest ray on the screen, share of the tile's height
    double screen_thickness = 0.08;  // a depth sample hides what lies up to this share of its depth behind it
};

// Reads every "shadows.*" parameter. Throws std::runtime_error naming the parameter for a
// value the declarations could not reject (an unknown method name).
ShadowSettings shadow_settings_from(const EffectParams& params);

}  // namespace glcast::slave::effects
