#include "slave/effects/winter/winter_settings.h"

#include <cmath>
#include <stdexcept>

namespace glcast::slave::effects {

std::vector<ParamSpec> winter_param_specs() {
    auto text = [](const char* name, const char* help) { return ParamSpec{name, 0, 0, 0, help, true}; };
    return {
        {"cover.spread", 40, 0, 180, "degrees: surfaces whose normal is within this angle of up (cover.up_*) hold snow"},
        {"cover.softness", 3, 0, 45, "degrees: half width of the soft transition around the spread angle"},
        text("cover.spread_mode", "uniform (default): one spread angle; random: the angle times a per-location factor "
                                  "((r + random_offset) * random_stepper)^random_exponent, r seeded noise in [0,1)"),
        {"cover.random_offset", 0.5, -1, 2, "random spread: offset added to the per-location random value"},
        {"cover.random_stepper", 1, 0, 4, "random spread: scale of (r + offset) (the radius stepper)"},
        {"cover.random_exponent", 1, 0.1, 8, "random spread: exponent of the per-location factor"},
        {"cover.random_scale", 2, 0.001, 1e6, "random spread: size of the regions sharing a spread factor, world units"},
        {"cover.density", 0.9, 0, 1, "fraction of an up-facing surface covered by snow (0: none, 1: all)"},
        {"cover.noise_scale", 0.8, 0.001, 1e6, "size of the snow patches, world units (eye units when cover.up_space=eye)"},
        {"cover.edge", 0.06, 0.001, 0.5, "softness of the patch borders (fraction of the density range)"},
        {"cover.seed", 1, 0, 4294967295.0, "seed of the snow patches and the random spread"},
        text("cover.up_space", "world: cover.up_* in world space, through the main view's modelview (eye space "
                               "when the frame has no view); eye: cover.up_* in eye space; auto (default unless "
                               "cover.up_* is given): the world's +Y or +Z, whichever the first view sees as up"),
        {"cover.up_x", 0, -1, 1, "x of the direction opposite to the snowfall"},
        {"cover.up_y", 1, -1, 1, "y of the direction opposite to the snowfall"},
        {"cover.up_z", 0, -1, 1, "z of the direction opposite to the snowfall"},
        text("cover.normals", "auto (default: vertex when the program lights its scene, else faceted), vertex, "
                              "faceted (re-rendered triangles' planes) or depth (from the depth buffer, no re-render)"),
        {"cover.build_frames", 0, 0, 1e9, "frames over which the cover builds up from nothing (0: complete at once)"},
        {"cover.brightness", 1, 0, 2, "scale of the snow's shaded color"},
        {"cover.lip", 0.004, 0, 0.05, "mean thickness of the snow rounded over lower edges (0.5 to 1.5 times this, "
                                      "seeded along the edge), fraction of the canvas height; 0: no lip"},
        {"cover.edge_angle", 40, 5, 175, "degrees: at a lower edge of the cover (lip, icicle roots) the surface below "
                                         "turns away by more than this"},
        text("cover.mask", "PNG stretched over the canvas: snow only where it is white and opaque "
                           "(luminance times alpha scales the cover); snow by texture"),
        {"icicles.seed", 1, 0, 4294967295.0, "seed of the icicles' placement, radius and growth"},
        {"icicles.density", 0.6, 0, 1, "fraction of the candidate columns along a lower edge that hold an icicle"},
        {"icicles.spacing", 0.012, 0.001, 0.5, "distance between candidate columns, fraction of the canvas height"},
        {"icicles.radius_min", 0.003, 0.0002, 0.1, "smallest root radius, fraction of the canvas height"},
        {"icicles.radius_max", 0.010, 0.0002, 0.1, "largest root radius, fraction of the canvas height"},
        {"icicles.length_max", 0.09, 0.001, 0.5,
         "length of an icicle of radius_max, fraction of the canvas height: L = length_max (r / radius_max)^(4/3)"},
        {"icicles.taper", 1, 0.2, 4, "shape: radius at fraction t of the length is r (1 - t)^taper"},
        {"icicles.refraction", 0.6, 0, 4, "sideways shift of the background seen through the ice, in icicle radii"},
        {"icicles.growth_frames", 0, 0, 1e9, "each icicle grows over this many frames, starting at a seeded frame "
                                             "below this count (0: fully grown at once)"},
    };
}

namespace {

std::string text_or(const EffectParams& params, const char* name, const char* fallback) {
    const std::string value = params.text(name);
    return value.empty() ? fallback : value;
}

[[noreturn]] void bad_choice(const char* name, const std::string& value, const char* choices) {
    throw std::runtime_error(std::string("effect parameter ") + name + " = \"" + value + "\": expected " + choices);
}

}  // namespace

WinterSettings winter_settings_from(const EffectParams& params) {
    WinterSettings s;
    CoverSettings& c = s.cover;
    c.spread_deg = params.number("cover.spread");
    c.softness_deg = params.number("cover.softness");
    const std::string spread_mode = text_or(params, "cover.spread_mode", "uniform");
    if (spread_mode == "random") c.random_spread = true;
    else if (spread_mode != "uniform") bad_choice("cover.spread_mode", spread_mode, "uniform or random");
    c.random_offset = params.number("cover.random_offset");
    c.random_stepper = params.number("cover.random_stepper");
    c.random_exponent = params.number("cover.random_exponent");
    c.random_scale = params.number("cover.random_scale");
    c.density = params.number("cover.density");
    c.noise_scale = params.number("cover.noise_scale");
    c.edge = params.number("cover.edge");
    c.seed = unsigned(params.number("cover.seed"));
    const bool up_given = params.has("cover.up_x") || params.has("cover.up_y") || params.has("cover.up_z");
    const std::string up_space = text_or(params, "cover.up_space", up_given ? "world" : "auto");
    if (up_space == "eye") c.up_in_world = false;
    else if (up_space == "auto") c.up_auto = true;
    else if (up_space != "world") bad_choice("cover.up_space", up_space, "world, eye or auto");
    c.up = {params.number("cover.up_x"), params.number("cover.up_y"), params.number("cover.up_z")};
    if (glm::length(c.up) < 1e-6) throw std::runtime_error("effect parameters cover.up_x/y/z: the up direction is zero");
    c.up = glm::normalize(c.up);
    const std::string normals = text_or(params, "cover.normals", "auto");
    if (normals == "auto") c.normals = NormalSource::Auto;
    else if (normals == "vertex") c.normals = NormalSource::Vertex;
    else if (normals == "faceted") c.normals = NormalSource::Faceted;
    else if (normals == "depth") c.normals = NormalSource::Depth;
    else bad_choice("cover.normals", normals, "auto, vertex, faceted or depth");
    c.build_frames = params.number("cover.build_frames");
    c.brightness = params.number("cover.brightness");
    c.lip = params.number("cover.lip");
    c.edge_angle_deg = params.number("cover.edge_angle");
    c.mask_path = params.text("cover.mask");
    if (!c.mask_path.empty()) {
        std::string error;
        if (!read_png(c.mask_path, c.mask, error)) throw std::runtime_error("effect parameter cover.mask: " + error);
    }

    IcicleSettings& i = s.icicles;
    i.seed = unsigned(params.number("icicles.seed"));
    i.density = params.number("icicles.density");
    i.spacing = params.number("icicles.spacing");
    i.radius_min = params.number("icicles.radius_min");
    i.radius_max = params.number("icicles.radius_max");
    i.length_max = params.number("icicles.length_max");
    i.taper = params.number("icicles.taper");
    i.refraction = params.number("icicles.refraction");
    i.growth_frames = params.number("icicles.growth_frames");
    if (i.radius_min > i.radius_max)
        throw std::runtime_error("effect parameters icicles.radius_min (" + std::to_string(i.radius_min) +
                                 ") is larger than icicles.radius_max (" + std::to_string(i.radius_max) + ")");
    return s;
}

}  // namespace glcast::slave::effects
