// Settings of the snow cover and icicle pass (docs/winter.md), read once from the effect
// parameters "cover.*" and "icicles.*" (declared by winter_param_specs() in winter_settings.cpp).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/image.h"
#include "slave/effects/effect_params.h"

namespace glcast::slave::effects {

// Where the surface normals come from (docs/winter.md, "Normals").
enum class NormalSource {
    Auto,     // vertex normals when the program lights its scene (it must send normals), else faceted
    Vertex,   // the program's glNormal / normal arrays, re-rendered with FrameView::redraw
    Faceted,  // the re-rendered triangles' own plane (derivatives of the eye position)
    Depth,    // reconstructed from the window's depth buffer, without re-rendering
};

struct CoverSettings {
    double spread_deg = 40;        // a surface whose normal is within this angle of "up" holds snow
    double softness_deg = 3;       // half width of the soft band around the spread angle
    bool random_spread = false;    // the random spread method (docs/winter.md): per-location spread factor
    double random_offset = 0.5, random_stepper = 1.0, random_exponent = 1.0;
    double random_scale = 2.0;     // feature size of the per-location spread factor, world units
    double density = 0.9;          // about this fraction of an up-facing surface is covered
    double noise_scale = 0.8;      // feature size of the snow patches, world units
    double edge = 0.06;            // softness of the patch borders, in noise units
    unsigned seed = 1;
    bool up_in_world = true;       // "up" in world space (through the main view's modelview), else eye space
    glm::dvec3 up{0, 1, 0};        // the direction opposite to the snowfall
    bool up_auto = false;          // `up`: the world axis the first main view sees as up (world_up_seen)
    NormalSource normals = NormalSource::Auto;
    double build_frames = 0;       // frames over which the cover builds up from nothing (0: at once)
    double brightness = 1.0;       // scale of the snow's shaded color
    double lip = 0.004;            // mean thickness of the rounded snow over lower edges, fraction of the canvas height
    double edge_angle_deg = 40;    // a lower edge: the surface below turns away by more than this
    std::string mask_path;         // PNG over the canvas: white opaque = snow allowed, black/transparent = none
    Image mask;                    // loaded when mask_path is set
};

struct IcicleSettings {
    unsigned seed = 1;
    double density = 0.6;          // fraction of the candidate columns along a lower edge that hold an icicle
    double spacing = 0.012;        // distance between candidate columns, fraction of the canvas height
    double radius_min = 0.003;     // root radius range, fraction of the canvas height
    double radius_max = 0.010;
    double length_max = 0.09;      // length of an icicle of radius_max: L = length_max (r / radius_max)^(4/3)
    double taper = 1.0;            // radius at fraction t of the length: r (1 - t)^taper
    double refraction = 0.6;       // sideways displacement of the background seen through the ice
    double growth_frames = 0;      // each icicle grows over this many frames from a seeded start (0: grown)
};

struct WinterSettings {
    CoverSettings cover;
    IcicleSettings icicles;
};

// Every "cover.*" and "icicles.*" parameter, in documentation order.
std::vector<ParamSpec> winter_param_specs();

// Reads the parameters and loads the mask image. Throws std::runtime_error naming the
// parameter for a value the declarations cannot reject (an unknown mode name, a mask file that
// cannot be read, radius_min above radius_max).
WinterSettings winter_settings_from(const EffectParams& params);

}  // namespace glcast::slave::effects
