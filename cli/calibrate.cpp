// `glcast calibrate SPEC.json --out DIR`: warp and blend maps for projectors of known pose and
// lens on a cylinder, dome or plane, written as the plain pair or as MPCDI with a display config;
// `--simulate WALL.json --outputs DIR --image PNG`: the installation previewed: each projector's
// output (a tile's frame) thrown onto the surface and unrolled (docs/projectors.md).
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/paths.h"
#include "common/image.h"
#include "display_configs/config_check.h"
#include "display_configs/display_config.h"
#include "display_configs/mpcdi.h"
#include "display_configs/projector_maps.h"
#include "display_configs/projector_model.h"

namespace glcast::cli {

using namespace glcast::slave;
using slave::config_check::FileProblem;
using slave::config_check::Validator;
using slave::config_check::read_regular_file;
using nlohmann::json;

namespace {

struct CalibrateArgs {
    std::string spec, out_dir, format = "plain", profile = "2d", simulate, outputs, image, reference;
    int scale = 1;  // --simulate: canvas pixels per side of one pixel of the unrolled picture
};

struct Spec {
    std::string name = "projectors";
    Surface surface;
    int canvas_width = 1200, canvas_height = 0, node_spacing = 8;
    std::vector<Projector> projectors;
};

double number(const json& j, const char* key, double fallback, double lo, double hi, const std::string& where) {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number() || !(j[key].get<double>() >= lo && j[key].get<double>() <= hi))
        throw std::runtime_error(where + "." + key + " must be a number from " + std::to_string(lo) + " to " +
                                 std::to_string(hi));
    return j[key].get<double>();
}

void pair_of(const json& j, const char* key, double& a, double& b, const std::string& where) {
    if (!j.contains(key)) return;
    if (!j[key].is_array() || j[key].size() != 2 || !j[key][0].is_number() || !j[key][1].is_number() ||
        !(j[key][0].get<double>() < j[key][1].get<double>()))
        throw std::runtime_error(where + "." + key + " must be [FROM, TO] with FROM < TO");
    a = j[key][0], b = j[key][1];
}

const char* const kSpecKeys[] = {"name", "canvas_width", "node_spacing", "surface", "projectors"};
const char* const kSurfaceKeys[] = {"kind", "radius", "distance", "azimuth", "height", "x", "y"};
const char* const kProjectorKeys[] = {"name", "position", "yaw", "pitch", "roll", "left", "right", "down", "up"};

// Read as a display config is (at most 1 MiB, a regular file), every key known: a misspelt one
// would otherwise leave its default in place unseen.
Spec read_spec(const std::string& path) {
    std::string text, file_kind, error;
    int error_number = 0;
    if (read_regular_file(path, kMaxDisplayConfigBytes, text, error_number, file_kind) != FileProblem::none)
        throw std::runtime_error(path + ": cannot be read as a file of at most 1 MiB" +
                                 (error_number ? std::string(": ") + std::strerror(error_number) : std::string()));
    json j = json::parse(text, nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw std::runtime_error(path + ": not a JSON object");
    Validator check(path, error);
    const bool known = check.check_keys(j, "", kSpecKeys) &&
                       (!j.contains("surface") || !j["surface"].is_object() ||
                        check.check_keys(j["surface"], "surface", kSurfaceKeys));
    if (!known) throw std::runtime_error(error);
    if (j.contains("projectors") && j["projectors"].is_array())
        for (size_t i = 0; i < j["projectors"].size() && i < 64; i++)
            if (j["projectors"][i].is_object() &&
                !check.check_keys(j["projectors"][i], "projectors[" + std::to_string(i) + "]", kProjectorKeys))
                throw std::runtime_error(error);
    Spec s;
    if (j.contains("name") && j["name"].is_string()) s.name = j["name"];
    // It names files (NAME.mpcdi in --out): a name, never a path (as tiles' names).
    if (!is_valid_display_name(s.name)) throw std::runtime_error(path + ": name is not a plain name (letters, digits, '_', '-', '.')");
    const json& surface = j.value("surface", json::object());
    const std::string kind = surface.value("kind", "cylinder");
    s.surface.kind = kind == "dome" ? Surface::dome : kind == "plane" ? Surface::plane : Surface::cylinder;
    if (kind != "dome" && kind != "plane" && kind != "cylinder")
        throw std::runtime_error(path + ": surface.kind \"" + kind + "\" (want cylinder, dome or plane)");
    const std::string w = path + ": surface";
    s.surface.radius = number(surface, "radius", s.surface.radius, 0.1, 1000, w);
    s.surface.distance = number(surface, "distance", s.surface.distance, 0.1, 1000, w);
    pair_of(surface, "azimuth", s.surface.azimuth_from, s.surface.azimuth_to, w);
    pair_of(surface, "height", s.surface.height_from, s.surface.height_to, w);
    pair_of(surface, "x", s.surface.x_from, s.surface.x_to, w);
    pair_of(surface, "y", s.surface.y_from, s.surface.y_to, w);
    s.canvas_width = int(number(j, "canvas_width", s.canvas_width, 16, 8192, path));
    // The height follows from the surface's shape: bounded as the width is, before any pixel.
    const double height = s.canvas_width / s.surface.aspect();
    if (!(height <= 8192))
        throw std::runtime_error(path + ": a canvas " + std::to_string(s.canvas_width) + " wide on this surface is " +
                                 std::to_string(std::llround(std::min(height, 1e12))) +
                                 " high, over 8192: give a smaller canvas_width, or a surface less tall");
    s.canvas_height = std::max(16, int(std::lround(height)));
    s.node_spacing = int(number(j, "node_spacing", s.node_spacing, 1, 256, path));
    if (!j.contains("projectors") || !j["projectors"].is_array() || j["projectors"].empty() || j["projectors"].size() > 64)
        throw std::runtime_error(path + ": projectors must list 1 to 64 projectors");
    for (size_t i = 0; i < j["projectors"].size(); i++) {
        const json& p = j["projectors"][i];
        const std::string where = path + ": projectors[" + std::to_string(i) + "]";
        Projector pr;
        pr.name = p.value("name", "p" + std::to_string(i + 1));
        if (!is_valid_display_name(pr.name)) throw std::runtime_error(where + ".name is not a plain name");
        if (p.contains("position")) {
            const json& pos = p["position"];
            if (!pos.is_array() || pos.size() != 3 || !pos[0].is_number() || !pos[1].is_number() || !pos[2].is_number())
                throw std::runtime_error(where + ".position must be [x, y, z] in metres");
            pr.position = {pos[0].get<double>(), pos[1].get<double>(), pos[2].get<double>()};
        }
        pr.yaw = number(p, "yaw", 0, -360, 360, where), pr.pitch = number(p, "pitch", 0, -90, 90, where);
        pr.roll = number(p, "roll", 0, -180, 180, where);
        pr.left = number(p, "left", pr.left, -89, 89, where), pr.right = number(p, "right", pr.right, -89, 89, where);
        pr.down = number(p, "down", pr.down, -89, 89, where), pr.up = number(p, "up", pr.up, -89, 89, where);
        if (!(pr.left < pr.right && pr.down < pr.up)) throw std::runtime_error(where + ": left < right and down < up");
        s.projectors.push_back(pr);
    }
    return s;
}

// A frustum as the display config and the MPCDI file both say it: to a ten-thousandth of a
// degree, so that the slave's check that a tile's view is its region's frustum holds exactly.
TileView view_of(const EyeFrustum& f) {
    auto round = [](double degrees) { return std::round(degrees * 1e4) / 1e4; };
    TileView v;
    v.enabled = true;
    v.yaw_deg = round(f.yaw), v.pitch_deg = round(f.pitch), v.roll_deg = 0;
    v.left_deg = round(f.left), v.right_deg = round(f.right), v.bottom_deg = round(f.down), v.top_deg = round(f.up);
    return v;
}

int calibrate(const CalibrateArgs& a) {
    const Spec s = read_spec(a.spec);
    std::string error;
    const bool three_d = a.profile == "3d";
    if (three_d && a.format != "mpcdi") throw std::runtime_error("--profile 3d is MPCDI's: give --format mpcdi too");
    if (!make_directories(a.out_dir, error)) throw std::runtime_error("--out: " + error);
    json tiles = json::array();
    std::vector<MpcdiRegionOut> regions;
    std::vector<std::pair<std::string, std::string>> files;
    for (size_t i = 0; i < s.projectors.size(); i++) {
        const Projector& p = s.projectors[i];
        const CanvasRect r = footprint(s.surface, p, s.canvas_width, s.canvas_height);
        if (r.width < 2 || r.height < 2) throw std::runtime_error("projector " + p.name + " lights none of the surface");
        const WarpMap warp = projector_warp(s.surface, p, r, s.canvas_width, s.canvas_height,
                                            r.width / s.node_spacing + 2, r.height / s.node_spacing + 2);
        const BlendMap blend = projector_blend(s.surface, s.projectors, i, r.width, r.height);
        FloatImage pfm;
        pfm.width = warp.width, pfm.height = warp.height, pfm.channels = 3;
        pfm.values.resize(size_t(warp.width) * warp.height * 3);
        // The 3D profile: the view from the eye that holds what it lights, and the points it lights.
        std::optional<EyeFrustum> frustum;
        if (three_d) {
            frustum = eye_frustum(s.surface, p);
            if (!frustum)
                throw std::runtime_error("projector " + p.name + ": no view from the eye holds what it lights (80 degrees "
                                         "or more from its middle): the 3D profile cannot describe it");
            pfm.values = projector_points(s.surface, p, warp.width, warp.height);
        }
        for (size_t n = 0; !three_d && n < size_t(warp.width) * warp.height; n++) {
            float u = warp.uv[n * 2], v = warp.uv[n * 2 + 1];
            if (a.format == "mpcdi" && !std::isnan(u))  // MPCDI's 2D profile: positions in the buffer (the canvas)
                u = float((u * r.width + r.x) / s.canvas_width), v = float((v * r.height + r.y) / s.canvas_height);
            pfm.values[n * 3] = u, pfm.values[n * 3 + 1] = v, pfm.values[n * 3 + 2] = 0;
        }
        json tile = {{"name", p.name}, {"x", r.x}, {"y", r.y}, {"width", r.width}, {"height", r.height}};
        const std::string warp_name = p.name + "_warp.pfm", blend_name = p.name + "_blend.png";
        const std::string blend_path = a.out_dir + "/" + blend_name;
        if (!write_blend_png(blend_path, blend, error)) throw std::runtime_error(error);
        if (a.format == "mpcdi") {
            std::ifstream png(blend_path, std::ios::binary);
            files.push_back({warp_name, pfm_bytes(pfm)});
            files.push_back({blend_name, std::string(std::istreambuf_iterator<char>(png), {})});
            std::remove(blend_path.c_str());
            MpcdiRegionOut region;
            region.id = p.name, region.width = r.width, region.height = r.height;
            region.rect = {double(r.x) / s.canvas_width, double(r.y) / s.canvas_height, double(r.width) / s.canvas_width,
                           double(r.height) / s.canvas_height};
            region.warp_entry = warp_name, region.alpha_entry = blend_name;
            if (frustum) {
                region.has_frustum = true;
                region.frustum = view_of(*frustum);
                const TileView& v = region.frustum;
                tile["view"] = {{"yaw", v.yaw_deg},         {"pitch", v.pitch_deg},   {"roll", v.roll_deg},
                                {"left", v.left_deg},       {"right", v.right_deg},   {"bottom", v.bottom_deg},
                                {"top", v.top_deg}};
            }
            regions.push_back(region);
            tile["mpcdi"] = s.name + ".mpcdi";
            tile["region"] = p.name;
        } else {
            if (!write_pfm(a.out_dir + "/" + warp_name, pfm, error)) throw std::runtime_error(error);
            tile["warp"] = warp_name;
            tile["blend"] = blend_name;
        }
        std::printf("%s: tile %dx%d at (%d, %d) of the canvas, warp %dx%d nodes\n", p.name.c_str(), r.width, r.height,
                    r.x, r.y, warp.width, warp.height);
        tiles.push_back(tile);
    }
    if (a.format == "mpcdi" &&
        !write_mpcdi(a.out_dir + "/" + s.name + ".mpcdi", s.canvas_width, s.canvas_height, regions, files, error))
        throw std::runtime_error(error);
    const json config = {{"name", s.name},
                         {"description", "projectors on a " + std::string(s.surface.kind == Surface::dome ? "dome"
                                                                          : s.surface.kind == Surface::plane ? "plane"
                                                                                                             : "cylinder") +
                                             ", made by glcast calibrate from " + a.spec},
                         {"canvas", {{"width", s.canvas_width}, {"height", s.canvas_height}}},
                         {"tiles", tiles}};
    std::ofstream wall(a.out_dir + "/wall.json");
    wall << config.dump(2) << "\n";
    wall.close();
    if (!wall) throw std::runtime_error(a.out_dir + "/wall.json: cannot be written");
    std::printf("canvas %dx%d; %s/wall.json\n", s.canvas_width, s.canvas_height, a.out_dir.c_str());
    return 0;
}

// Bilinear, at continuous coordinates (pixel centres at +0.5), clamped.
glm::dvec3 sample(const Image& im, double x, double y) {
    x = std::clamp(x - 0.5, 0.0, im.width - 1.0), y = std::clamp(y - 0.5, 0.0, im.height - 1.0);
    const int x0 = int(x), y0 = int(y), x1 = std::min(x0 + 1, im.width - 1), y1 = std::min(y0 + 1, im.height - 1);
    const double fx = x - x0, fy = y - y0;
    auto at = [&](int px, int py) {
        const uint8_t* p = &im.rgba[(size_t(py) * im.width + px) * 4];
        return glm::dvec3(p[0], p[1], p[2]);
    };
    return glm::mix(glm::mix(at(x0, y0), at(x1, y0), fx), glm::mix(at(x0, y1), at(x1, y1), fx), fy);
}

double sample_blend(const BlendMap& b, double x, double y) {  // x, y: 0..1 over the output
    const double px = std::clamp(x * b.width - 0.5, 0.0, b.width - 1.0), py = std::clamp(y * b.height - 0.5, 0.0, b.height - 1.0);
    const int x0 = int(px), y0 = int(py), x1 = std::min(x0 + 1, b.width - 1), y1 = std::min(y0 + 1, b.height - 1);
    const double fx = px - x0, fy = py - y0;
    auto at = [&](int i, int j) { return double(b.rgb[(size_t(j) * b.width + i) * 3]); };
    return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) + (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
}

int simulate(const CalibrateArgs& a) {
    const Spec s = read_spec(a.spec);
    DisplayConfig config;
    std::string error;
    if (!load_display_config(a.simulate, config, error)) throw std::runtime_error(error);
    std::vector<Image> outputs;
    std::vector<BlendMap> blends;
    for (const Projector& p : s.projectors) {
        const Tile* t = config.find(p.name);
        if (!t) throw std::runtime_error(a.simulate + ": no tile " + p.name);
        Image im;
        if (!read_png(a.outputs + "/" + p.name + ".png", im, error)) throw std::runtime_error(error);
        if (im.width != t->width || im.height != t->height)
            throw std::runtime_error(a.outputs + "/" + p.name + ".png is " + std::to_string(im.width) + "x" +
                                     std::to_string(im.height) + ", tile " + p.name + " is " + std::to_string(t->width) +
                                     "x" + std::to_string(t->height));
        outputs.push_back(std::move(im));
        ProjectorMaps maps;
        const bool ok = t->mpcdi.empty()
                            ? load_plain_maps("", relative_to(a.simulate, t->blend), maps, error)
                            : load_mpcdi_region(relative_to(a.simulate, t->mpcdi), t->region, BufferRect{}, maps, error,
                                                t->view.enabled ? &t->view : nullptr);
        if (!ok || !maps.has_alpha) throw std::runtime_error("tile " + p.name + ": its blend: " + error);
        blends.push_back(maps.alpha);
    }
    // The unrolled picture: each of its pixels the mean of scale x scale points of the canvas (a
    // projector lights the surface at its own resolution; an eye, or a camera, averages).
    const int k = a.scale;
    Image canvas;
    canvas.width = config.canvas_width / k, canvas.height = config.canvas_height / k;
    canvas.rgba.assign(size_t(canvas.width) * canvas.height * 4, 0);
    uint64_t covered = 0, overlap = 0, over_2 = 0, points = 0;
    // Where two projectors overlap (each with a blend of 0.2 to 0.8 on the whole unrolled pixel),
    // how far what they show differs, unblended: they light one point of the surface, so both
    // should show one thing there.
    double agreement_sum = 0;
    uint64_t agreement_points = 0, agreement_far = 0;
    double worst = 0;
    for (int y = 0; y < canvas.height; y++)
        for (int x = 0; x < canvas.width; x++) {
            glm::dvec3 light(0.0), shown_by[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
            int lit = 0, both = 0;
            for (int sy = 0; sy < k; sy++)
                for (int sx = 0; sx < k; sx++) {
                    const auto point = s.surface.roll({(x * k + sx + 0.5) / config.canvas_width,
                                                       (y * k + sy + 0.5) / config.canvas_height});
                    if (!point) continue;
                    double alpha = 0;
                    int reaching = 0;
                    glm::dvec3 first(-1.0);
                    for (size_t i = 0; i < s.projectors.size(); i++) {
                        const auto o = s.projectors[i].project(*point);
                        if (!o) continue;
                        reaching++;
                        // (unblended, to compare what two projectors show at one point of the surface)
                        const glm::dvec3 shown = sample(outputs[i], o->x * outputs[i].width, o->y * outputs[i].height);
                        const double b = sample_blend(blends[i], o->x, o->y);
                        light += shown;
                        alpha += b;
                        const glm::dvec3 unblended = b > 0.2 && b < 0.8 ? shown / b : glm::dvec3(-1.0);
                        if (reaching == 1) first = unblended;
                        else if (reaching == 2 && first.x >= 0 && unblended.x >= 0)
                            shown_by[0] += first, shown_by[1] += unblended, both++;
                    }
                    if (!reaching) continue;
                    lit++, points++;
                    overlap += reaching > 1;
                    const double deviation = std::fabs(alpha - 1);
                    worst = std::max(worst, deviation);
                    over_2 += deviation > 0.02;
                }
            if (both == k * k) {  // two projectors overlap on the whole pixel: as the picture, each one's mean
                const glm::dvec3 d = glm::abs(shown_by[0] - shown_by[1]) / double(both);
                agreement_sum += (d.x + d.y + d.z) / 3, agreement_points++;
                agreement_far += std::max(d.x, std::max(d.y, d.z)) > 8;
            }
            if (lit < k * k) continue;  // a pixel the projectors light only in part: not compared
            covered++;
            uint8_t* px = &canvas.rgba[(size_t(y) * canvas.width + x) * 4];
            for (int c = 0; c < 3; c++) px[c] = uint8_t(std::clamp(std::lround(light[c] / lit), 0L, 255L));
            px[3] = 255;
        }
    if (!write_png(a.image, canvas, error)) throw std::runtime_error(error);
    if (!a.reference.empty()) {  // the canvas as one replay shows it: what the projectors should make
        Image ref;
        if (!read_png(a.reference, ref, error)) throw std::runtime_error(error);
        if (ref.width != config.canvas_width || ref.height != config.canvas_height)
            throw std::runtime_error(a.reference + " is not the canvas's size");
        ref = scaled_down(ref, k);
        double sum = 0;
        uint64_t n = 0, far = 0;
        for (size_t i = 0; i < size_t(canvas.width) * canvas.height; i++) {
            if (!canvas.rgba[i * 4 + 3]) continue;  // no projector reaches it
            int worst_channel = 0;
            for (int c = 0; c < 3; c++) {
                const int d = std::abs(int(canvas.rgba[i * 4 + c]) - int(ref.rgba[i * 4 + c]));
                sum += d, worst_channel = std::max(worst_channel, d);
            }
            n++, far += worst_channel > 8;
        }
        std::printf("against %s: mean difference %.3f levels, %.3f%% of pixels more than 8 levels off\n",
                    a.reference.c_str(), n ? sum / (3.0 * n) : 0.0, n ? 100.0 * far / n : 0.0);
    }
    std::printf("where two projectors overlap: %llu pixels, mean difference %.3f levels between them, %.3f%% more "
                "than 8 levels off\n", (unsigned long long)agreement_points,
                agreement_points ? agreement_sum / agreement_points : 0.0,
                agreement_points ? 100.0 * agreement_far / agreement_points : 0.0);
    std::printf("unrolled %dx%d: %llu pixels lit whole; of %llu canvas points lit, %llu by more than one projector; "
                "blend sum: %llu points more than 2%% off 1 (%.4f%%), the worst %.4f off\n",
                canvas.width, canvas.height, (unsigned long long)covered, (unsigned long long)points,
                (unsigned long long)overlap, (unsigned long long)over_2, points ? 100.0 * over_2 / points : 0.0, worst);
    return 0;
}

}  // namespace

Command add_calibrate(CLI::App& glcast) {
    auto a = std::make_shared<CalibrateArgs>();
    CLI::App* app = glcast.add_subcommand(
        "calibrate", "warp and blend maps for projectors on a cylinder, dome or plane; preview the installation");
    app->footer("SPEC.json gives the surface and each projector's pose and lens (docs/projectors.md). With --out, writes\n"
                "DIR/wall.json (a display config: one tile per projector) and its maps; with --simulate, throws each\n"
                "projector's output (OUTPUTS/NAME.png, a frame of its tile) onto the surface and unrolls it.");
    app->add_option("SPEC", a->spec, "the installation: surface and projectors (JSON)")->required();
    app->add_option("--out", a->out_dir, "write the display config and the maps into DIR")->type_name("DIR");
    app->add_option("--format", a->format, "plain (a PFM warp and a PNG blend per projector, the default) or mpcdi")
        ->check(CLI::IsMember({"plain", "mpcdi"}));
    app->add_option("--profile", a->profile,
                    "with --format mpcdi: 2d (the canvas stretched over the surface, the default) or 3d (each\n"
                    "projector a view from the viewer's eye at the room's origin: the program's camera turned)")
        ->check(CLI::IsMember({"2d", "3d"}));
    app->add_option("--simulate", a->simulate, "the display config --out wrote: preview the installation")
        ->type_name("WALL.json");
    app->add_option("--outputs", a->outputs, "with --simulate: a folder of each projector's output, NAME.png")
        ->type_name("DIR");
    app->add_option("--image", a->image, "with --simulate: the unrolled picture, a PNG of the canvas")->type_name("PNG");
    add_int(*app, "--scale", a->scale, 1, 16,
            "with --simulate: canvas pixels per side of one unrolled pixel (default 1): the projectors and\n"
            "the tiles at K times the picture's resolution")
        ->type_name("K");
    app->add_option("--reference", a->reference,
                    "with --simulate: the canvas as one replay shows it; prints how far the unrolled picture is")
        ->type_name("PNG");
    return {app, [a](const std::vector<std::string>&) {
                try {
                    if (!a->simulate.empty()) {
                        if (a->outputs.empty() || a->image.empty()) usage_error("--simulate", "needs --outputs and --image");
                        return simulate(*a);
                    }
                    if (a->out_dir.empty()) usage_error("--out", "give --out DIR (or --simulate)");
                    return calibrate(*a);
                } catch (const std::runtime_error& e) {
                    std::fprintf(stderr, "glcast calibrate: %s\n", e.what());
                    return 1;
                }
            }};
}

}  // namespace glcast::cli
