#include "display_configs/mpcdi.h"

#include <tinyxml2.h>
#include <zip.h>

#include <strings.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>

#include "display_configs/projector_maps.h"
#include "slave/view_correction.h"

namespace glcast::slave {

namespace {

struct ZipCloser {
    void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
    void operator()(zip_file_t* f) const { zip_fclose(f); }
};

// An entry name glcast will read: relative, inside the archive, plain.
bool safe_entry_name(const std::string& name) {
    if (name.empty() || name.size() > 255 || name[0] == '/' || name.find('\\') != std::string::npos) return false;
    size_t start = 0;
    while (start <= name.size()) {
        size_t slash = name.find('/', start);
        if (slash == std::string::npos) slash = name.size();
        const std::string part = name.substr(start, slash - start);
        if (part == ".." || part == ".") return false;
        start = slash + 1;
    }
    return std::all_of(name.begin(), name.end(), [](char c) { return uint8_t(c) >= 0x20 && c != 0x7f; });
}

class Archive {
public:
    bool open(const std::string& path, std::string& error) {
        path_ = path;
        int code = 0;
        zip_.reset(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &code));
        if (!zip_) {
            zip_error_t e;
            zip_error_init_with_code(&e, code);
            error = path + ": not a readable MPCDI archive (zip: " + zip_error_strerror(&e) + ")";
            zip_error_fini(&e);
            return false;
        }
        const zip_int64_t n = zip_get_num_entries(zip_.get(), 0);
        if (n < 0 || uint64_t(n) > kMaxMpcdiEntries) {
            error = path + ": " + std::to_string(n) + " entries, more than an MPCDI file may have (" +
                    std::to_string(kMaxMpcdiEntries) + ")";
            return false;
        }
        for (zip_int64_t i = 0; i < n; i++) {
            zip_stat_t st;
            if (zip_stat_index(zip_.get(), zip_uint64_t(i), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME)) {
                error = path + ": entry " + std::to_string(i) + " cannot be read";
                return false;
            }
            const std::string name = st.name;
            if (!name.empty() && name.back() == '/') continue;  // a folder
            if (!safe_entry_name(name)) {
                error = path + ": entry \"" + name + "\": a name that leaves the archive or is not plain (\"..\", an "
                        "absolute path, control characters)";
                return false;
            }
            if (!(st.valid & ZIP_STAT_SIZE) || !(st.valid & ZIP_STAT_COMP_SIZE) || st.size > kMaxMpcdiEntryBytes) {
                error = path + ": entry " + name + ": " + std::to_string(st.size) + " bytes uncompressed, more than " +
                        std::to_string(kMaxMpcdiEntryBytes);
                return false;
            }
            if (st.size > 1024 * 1024 && st.size > kMaxMpcdiRatio * std::max<uint64_t>(1, st.comp_size)) {
                error = path + ": entry " + name + ": compressed " + std::to_string(st.size / std::max<uint64_t>(1, st.comp_size)) +
                        " to 1 (" + std::to_string(st.comp_size) + " bytes for " + std::to_string(st.size) +
                        "): a zip bomb, not a map";
                return false;
            }
            entries_[name] = {zip_uint64_t(i), st.size};
        }
        return true;
    }

    bool has(const std::string& name) const { return entries_.count(name) != 0; }
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& [name, e] : entries_) out.push_back(name);
        return out;
    }

    // The entry's bytes: at most the size its header declares (a lying header is caught here).
    bool read(const std::string& name, std::string& out, std::string& error) const {
        auto it = entries_.find(name);
        if (it == entries_.end()) {
            error = path_ + ": no entry \"" + name + "\" in the archive";
            return false;
        }
        std::unique_ptr<zip_file_t, ZipFileCloser> f(zip_fopen_index(zip_.get(), it->second.index, 0));
        if (!f) {
            error = path_ + ": entry " + name + ": " + zip_strerror(zip_.get());
            return false;
        }
        out.resize(it->second.size);
        const zip_int64_t got = out.empty() ? 0 : zip_fread(f.get(), out.data(), out.size());
        char extra;
        if (got != zip_int64_t(out.size()) || zip_fread(f.get(), &extra, 1) != 0) {
            error = path_ + ": entry " + name + ": its data is not the size its header says (or is corrupt: " +
                    zip_file_strerror(f.get()) + ")";
            return false;
        }
        return true;
    }

private:
    struct Entry {
        zip_uint64_t index;
        uint64_t size;
    };
    std::string path_;
    std::unique_ptr<zip_t, ZipCloser> zip_;
    std::map<std::string, Entry> entries_;
};

const char* text_of(const tinyxml2::XMLElement* parent, const char* child) {
    const tinyxml2::XMLElement* e = parent ? parent->FirstChildElement(child) : nullptr;
    return e && e->GetText() ? e->GetText() : nullptr;
}

// An attribute whose name MPCDI writers spell differently (Xresolution, xResolution, xresolution).
const char* attribute_any_case(const tinyxml2::XMLElement* e, const char* name) {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next())
        if (strcasecmp(a->Name(), name) == 0) return a->Value();
    return nullptr;
}

bool positive_int(const char* text, int& out) {
    if (!text) return false;
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (*end || v < 1 || v > kMaxMapSide) return false;
    out = int(v);
    return true;
}

// 3D profile: the region's frustum, which the tile's view must be.
bool frustum_is_view(const tinyxml2::XMLElement* region, const TileView* view, const std::string& where, std::string& error) {
    const tinyxml2::XMLElement* f = region->FirstChildElement("frustum");
    if (!f) {
        error = where + "a region of the 3D profile needs its <frustum>";
        return false;
    }
    struct Angle {
        const char* element;
        double view_value;
    } angles[] = {{"yaw", view ? view->yaw_deg : 0},          {"pitch", view ? view->pitch_deg : 0},
                  {"roll", view ? view->roll_deg : 0},        {"leftAngle", view ? view->left_deg : 0},
                  {"rightAngle", view ? view->right_deg : 0}, {"downAngle", view ? view->bottom_deg : 0},
                  {"upAngle", view ? view->top_deg : 0}};
    std::string frustum;
    bool same = view && view->enabled && !view->screen;
    for (const Angle& a : angles) {
        const char* text = text_of(f, a.element);
        char* end = nullptr;
        const double v = text ? std::strtod(text, &end) : NAN;
        if (!text || *end || !std::isfinite(v)) {
            error = where + "the frustum's <" + a.element + "> is not a number";
            return false;
        }
        char part[64];
        std::snprintf(part, sizeof part, "%s%s %g", frustum.empty() ? "" : ", ", a.element, v);
        frustum += part;
        same = same && std::fabs(v - a.view_value) < 1e-3;
    }
    if (!same) {
        error = where + "a region of the 3D profile is rendered from its frustum (" + frustum +
                "): give the tile a \"view\" of those angles (yaw, pitch, roll, left, right, bottom, top)";
        return false;
    }
    if (const tinyxml2::XMLElement* c = region->FirstChildElement("coordinateFrame")) {
        // The points' axes: glcast's (x right, y up, -z ahead) is yaw (0,-1,0), pitch (1,0,0), roll (0,0,-1).
        const char* names[9] = {"yawx", "yawy", "yawz", "pitchx", "pitchy", "pitchz", "rollx", "rolly", "rollz"};
        const double want[9] = {0, -1, 0, 1, 0, 0, 0, 0, -1};
        for (int i = 0; i < 9; i++) {
            const char* text = text_of(c, names[i]);
            if (text && std::fabs(std::strtod(text, nullptr) - want[i]) > 1e-6) {
                error = where + "a <coordinateFrame> other than x right, y up, z towards the viewer is not supported";
                return false;
            }
        }
    }
    return true;
}

// 3D profile: each node's screen point (relative to the eye) projected through the view into
// the tile's image, in place (u, v, 0); behind the eye or not finite: NaN (black).
bool points_to_warp(FloatImage& pfm, const TileView& view, const std::string& name, std::string& error) {
    if (pfm.channels != 3) {
        error = name + ": a warp of the 3D profile holds 3D points (PF, 3 channels)";
        return false;
    }
    ViewCorrection camera;  // the tile's own, as the slave renders it
    camera.enabled = true;
    camera.yaw_deg = view.yaw_deg, camera.pitch_deg = view.pitch_deg, camera.roll_deg = view.roll_deg;
    camera.left_deg = view.left_deg, camera.right_deg = view.right_deg;
    camera.bottom_deg = view.bottom_deg, camera.top_deg = view.top_deg;
    for (size_t i = 0; i < pfm.values.size(); i += 3) {
        float* p = &pfm.values[i];
        glm::dvec2 uv(NAN);
        const bool seen = std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]) &&
                          camera.image_position(glm::dvec3(p[0], p[1], p[2]), uv);
        p[0] = seen ? float(uv.x) : NAN;
        p[1] = seen ? float(uv.y) : NAN;
        p[2] = 0;
    }
    return true;
}

}  // namespace

bool load_mpcdi_region(const std::string& path, const std::string& region, const BufferRect& tile, ProjectorMaps& out,
                       std::string& error, const TileView* view) {
    Archive archive;
    if (!archive.open(path, error)) return false;
    std::string xml_name = archive.has("mpcdi.xml") ? "mpcdi.xml" : "";
    if (xml_name.empty()) {
        error = path + ": no mpcdi.xml in the archive (entries:";
        for (const std::string& n : archive.names()) error += " " + n;
        error += ")";
        return false;
    }
    std::string xml;
    if (!archive.read(xml_name, xml, error)) return false;
    tinyxml2::XMLDocument doc;
    if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
        error = path + ": mpcdi.xml: " + (doc.ErrorStr() ? doc.ErrorStr() : "not XML") + " (line " +
                std::to_string(doc.ErrorLineNum()) + ")";
        return false;
    }
    const tinyxml2::XMLElement* root = doc.FirstChildElement("MPCDI");
    if (!root) {
        error = path + ": mpcdi.xml: the root element is not <MPCDI>";
        return false;
    }
    const char* profile = root->Attribute("profile");
    const std::string where = path + ": mpcdi.xml: ";
    if (!profile || (std::string(profile) != "2d" && std::string(profile) != "3d")) {
        error = where + "profile \"" + (profile ? profile : "") + "\": glcast reads the 2D media (\"2d\") and 3D "
                "simulation (\"3d\") profiles; advanced 3D (\"a3\") and shader lamps (\"sl\") are not supported";
        return false;
    }
    const bool three_d = std::string(profile) == "3d";
    // The region: in display/buffer/region.
    const tinyxml2::XMLElement* found = nullptr;
    std::string known;
    const tinyxml2::XMLElement* display = root->FirstChildElement("display");
    for (const tinyxml2::XMLElement* b = display ? display->FirstChildElement("buffer") : nullptr; b;
         b = b->NextSiblingElement("buffer"))
        for (const tinyxml2::XMLElement* r = b->FirstChildElement("region"); r; r = r->NextSiblingElement("region")) {
            const char* id = r->Attribute("id");
            if (!id) continue;
            known += std::string(known.empty() ? "" : ", ") + id;
            if (region == id) found = r;
        }
    if (!found) {
        error = where + "no region \"" + region + "\" (regions: " + (known.empty() ? "none" : known) + ")";
        return false;
    }
    int width = 0, height = 0;
    if (!positive_int(attribute_any_case(found, "xResolution"), width) ||
        !positive_int(attribute_any_case(found, "yResolution"), height)) {
        error = where + "region " + region + ": its xResolution and yResolution must be whole numbers of 1 to " +
                std::to_string(kMaxMapSide);
        return false;
    }
    if (three_d && !frustum_is_view(found, view, where + "region " + region + ": ", error)) return false;
    // Its files: files/fileset region="ID" (some writers put the fileset inside the region).
    const tinyxml2::XMLElement* fileset = nullptr;
    const tinyxml2::XMLElement* files = root->FirstChildElement("files");
    for (const tinyxml2::XMLElement* f = files ? files->FirstChildElement("fileset") : nullptr; f && !fileset;
         f = f->NextSiblingElement("fileset"))
        if (const char* r = f->Attribute("region"); r && region == r) fileset = f;
    if (!fileset) fileset = found->FirstChildElement("fileset");
    if (!fileset) {
        error = where + "no <fileset region=\"" + region + "\"> (its warp and blend)";
        return false;
    }
    ProjectorMaps m;
    m.source = path + " region " + region;
    if (const tinyxml2::XMLElement* g = fileset->FirstChildElement("geometryWarpFile")) {
        const char* entry = text_of(g, "path");
        if (!entry) {
            error = where + "region " + region + ": <geometryWarpFile> has no <path>";
            return false;
        }
        if (const char* interpolation = text_of(g, "interpolation"); interpolation && std::string(interpolation) != "linear") {
            error = where + "region " + region + ": interpolation \"" + interpolation + "\": only linear is supported";
            return false;
        }
        std::string bytes;
        FloatImage pfm;
        if (!safe_entry_name(entry)) {
            error = where + "region " + region + ": the warp's path \"" + entry + "\" leaves the archive";
            return false;
        }
        if (!archive.read(entry, bytes, error) || !read_pfm_bytes(bytes, path + ": " + entry, pfm, error))
            return false;
        if (three_d && !points_to_warp(pfm, *view, path + ": " + entry, error)) return false;
        if (!warp_from_pfm(pfm, path + ": " + entry, m.warp, error)) return false;
        int declared = 0;
        if ((text_of(g, "xres") && (!positive_int(text_of(g, "xres"), declared) || declared != pfm.width)) ||
            (text_of(g, "yres") && (!positive_int(text_of(g, "yres"), declared) || declared != pfm.height))) {
            error = path + ": " + entry + ": the warp is " + std::to_string(pfm.width) + "x" + std::to_string(pfm.height) +
                    " nodes, not the xres and yres mpcdi.xml gives it";
            return false;
        }
        // From buffer coordinates to the tile's rendered image.
        for (size_t i = 0; !three_d && i < m.warp.uv.size(); i += 2) {
            m.warp.uv[i] = float((m.warp.uv[i] - tile.x) / tile.width);
            m.warp.uv[i + 1] = float((m.warp.uv[i + 1] - tile.y) / tile.height);
        }
        m.has_warp = true;
    }
    struct MapEntry {
        const char* element;
        BlendMap* map;
        bool* has;
    } maps[] = {{"alphaMap", &m.alpha, &m.has_alpha}, {"betaMap", &m.beta, &m.has_beta}};
    for (const MapEntry& me : maps) {
        const tinyxml2::XMLElement* e = fileset->FirstChildElement(me.element);
        if (!e) continue;
        const char* entry = text_of(e, "path");
        if (!entry || !safe_entry_name(entry)) {
            error = where + "region " + region + ": <" + me.element + "> has no <path>, or one that leaves the archive";
            return false;
        }
        std::string bytes;
        if (!archive.read(entry, bytes, error) || !blend_from_png(bytes, path + ": " + entry, *me.map, error))
            return false;
        if (me.map->width > width || me.map->height > height) {
            error = path + ": " + entry + ": a " + me.element + " of " + std::to_string(me.map->width) + "x" +
                    std::to_string(me.map->height) + " for a region of " + std::to_string(width) + "x" +
                    std::to_string(height) + " (a map is the region's size or smaller)";
            return false;
        }
        *me.has = true;
    }
    if (!m.any()) {
        error = where + "region " + region + ": its fileset has no geometryWarpFile, alphaMap or betaMap";
        return false;
    }
    out = std::move(m);
    return true;
}

bool write_mpcdi(const std::string& path, int buffer_width, int buffer_height, const std::vector<MpcdiRegionOut>& regions,
                 const std::vector<std::pair<std::string, std::string>>& files, std::string& error) {
    tinyxml2::XMLDocument doc;
    doc.InsertEndChild(doc.NewDeclaration());
    tinyxml2::XMLElement* root = doc.NewElement("MPCDI");
    doc.InsertEndChild(root);
    const bool three_d = !regions.empty() && regions.front().has_frustum;
    root->SetAttribute("profile", three_d ? "3d" : "2d");
    root->SetAttribute("geometry", "1");
    root->SetAttribute("color", "1");
    root->SetAttribute("version", "1.0");
    tinyxml2::XMLElement* display = root->InsertNewChildElement("display");
    tinyxml2::XMLElement* buffer = display->InsertNewChildElement("buffer");
    buffer->SetAttribute("id", "canvas");
    buffer->SetAttribute("Xresolution", buffer_width);
    buffer->SetAttribute("Yresolution", buffer_height);
    tinyxml2::XMLElement* file_list = root->InsertNewChildElement("files");
    for (const MpcdiRegionOut& r : regions) {
        tinyxml2::XMLElement* region = buffer->InsertNewChildElement("region");
        region->SetAttribute("id", r.id.c_str());
        region->SetAttribute("Xresolution", r.width);
        region->SetAttribute("Yresolution", r.height);
        region->SetAttribute("x", r.rect.x);
        region->SetAttribute("y", r.rect.y);
        region->SetAttribute("xsize", r.rect.width);
        region->SetAttribute("ysize", r.rect.height);
        if (three_d) {
            tinyxml2::XMLElement* frustum = region->InsertNewChildElement("frustum");
            const std::pair<const char*, double> angles[] = {
                {"yaw", r.frustum.yaw_deg},        {"pitch", r.frustum.pitch_deg},      {"roll", r.frustum.roll_deg},
                {"rightAngle", r.frustum.right_deg}, {"leftAngle", r.frustum.left_deg},
                {"upAngle", r.frustum.top_deg},    {"downAngle", r.frustum.bottom_deg}};
            for (const auto& [name, value] : angles) frustum->InsertNewChildElement(name)->SetText(value);
        }
        tinyxml2::XMLElement* fileset = file_list->InsertNewChildElement("fileset");
        fileset->SetAttribute("region", r.id.c_str());
        tinyxml2::XMLElement* warp = fileset->InsertNewChildElement("geometryWarpFile");
        warp->InsertNewChildElement("path")->SetText(r.warp_entry.c_str());
        warp->InsertNewChildElement("interpolation")->SetText("linear");
        warp->InsertNewChildElement("componentDepth")->SetText(3);
        warp->InsertNewChildElement("bitDepth")->SetText(32);
        tinyxml2::XMLElement* alpha = fileset->InsertNewChildElement("alphaMap");
        alpha->InsertNewChildElement("path")->SetText(r.alpha_entry.c_str());
        alpha->InsertNewChildElement("componentDepth")->SetText(1);
        alpha->InsertNewChildElement("bitDepth")->SetText(8);
        alpha->InsertNewChildElement("gammaEmbedded")->SetText("1.0");
    }
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    const std::string xml = printer.CStr();
    int code = 0;
    std::remove(path.c_str());
    zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
    if (!z) {
        error = path + ": cannot be written (zip error " + std::to_string(code) + ")";
        return false;
    }
    // zip_source_buffer keeps pointers until zip_close: the texts live until then.
    std::vector<std::pair<std::string, std::string>> all = files;
    all.insert(all.begin(), {"mpcdi.xml", xml});
    for (const auto& [name, bytes] : all) {
        zip_source_t* s = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
        if (!s || zip_file_add(z, name.c_str(), s, ZIP_FL_OVERWRITE | ZIP_FL_ENC_UTF_8) < 0) {
            if (s) zip_source_free(s);
            error = path + ": entry " + name + ": " + zip_strerror(z);
            zip_discard(z);
            return false;
        }
    }
    if (zip_close(z) != 0) {
        error = path + ": " + zip_strerror(z);
        zip_discard(z);
        return false;
    }
    return true;
}

}  // namespace glcast::slave
