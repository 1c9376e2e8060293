// Display configs (display_configs/display_config.h): the shipped files load with their stated geometry,
// every validation rule gives its exact message, and no input crashes the loader.
//
// Alone, from the repository root:
//   g++ -std=c++17 -DGLCAST_SOURCE_DIR=\"$PWD\" -I. display_configs/display_config.cpp tests/unit/display_config_test.cpp
//       -lgtest -lgtest_main -pthread
#include "display_configs/display_config.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <string>
#include <vector>

#ifndef GLCAST_SOURCE_DIR
#error "GLCAST_SOURCE_DIR must name the repository root"
#endif

using namespace glcast::slave;

namespace {

std::string config_path(const std::string& file) { return std::string(GLCAST_SOURCE_DIR) + "/display_configs/" + file; }

DisplayConfig load_ok(const std::string& file) {
    DisplayConfig c;
    std::string error;
    EXPECT_TRUE(load_display_config(config_path(file), c, error)) << error;
    EXPECT_EQ(error, "");
    return c;
}

// Parses `text` as "wall.json", expects failure and returns the message.
std::string error_of(const std::string& text) {
    DisplayConfig c;
    std::string error;
    EXPECT_FALSE(parse_display_config(text, "wall.json", c, error)) << "accepted:\n" << text;
    EXPECT_FALSE(error.empty());
    return error;
}

DisplayConfig parse_ok(const std::string& text) {
    DisplayConfig c;
    std::string error;
    EXPECT_TRUE(parse_display_config(text, "wall.json", c, error)) << error << "\n" << text;
    return c;
}

// A valid planar config with one replaceable spot per test: `tile1` is the second tile.
std::string planar(const std::string& tile1 = R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})",
                   const std::string& extra = "") {
    return R"({
  "name": "wall",
  "canvas": {"width": 1280, "height": 480},
  "tiles": [
    {"name": "a", "x": 0, "y": 0, "width": 640, "height": 480},
    )" + tile1 + R"(
  ])" + extra + "\n}\n";
}

// A valid view config; `view` is the first tile's "view" object.
std::string viewed(const std::string& view, const std::string& extra = "") {
    return R"({"name": "dome", "tiles": [{"name": "t0", "width": 800, "height": 600, "view": )" + view +
           "}]" + extra + "}";
}

void expect_contains(const std::string& text, const std::string& part) {
    EXPECT_NE(text.find(part), std::string::npos) << "expected \"" << part << "\" in:\n" << text;
}

}  // namespace

// ---- shipped configs --------------------------------------------------------------------

TEST(DisplayConfigShipped, Single) {
    DisplayConfig c = load_ok("single.json");
    EXPECT_EQ(c.name, "single");
    EXPECT_EQ(c.canvas_width, 1280);
    EXPECT_EQ(c.canvas_height, 720);
    ASSERT_EQ(c.tiles.size(), 1u);
    const Tile& t = c.tiles[0];
    EXPECT_EQ(t.x, 0);
    EXPECT_EQ(t.y, 0);
    EXPECT_EQ(t.width, 1280);
    EXPECT_EQ(t.height, 720);
    EXPECT_FALSE(t.view.enabled);
    EXPECT_FALSE(c.swap_barrier);
    EXPECT_TRUE(c.effects.empty());
}

TEST(DisplayConfigShipped, Wall2x2) {
    DisplayConfig c = load_ok("wall-2x2.json");
    EXPECT_EQ(c.name, "wall-2x2");
    EXPECT_EQ(c.canvas_width, 1280);
    EXPECT_EQ(c.canvas_height, 960);
    ASSERT_EQ(c.tiles.size(), 4u);
    struct {
        const char* name;
        int x, y;
    } expected[] = {{"top-left", 0, 0}, {"top-right", 640, 0}, {"bottom-left", 0, 480}, {"bottom-right", 640, 480}};
    for (const auto& e : expected) {
        const Tile* t = c.find(e.name);
        ASSERT_NE(t, nullptr) << e.name;
        EXPECT_EQ(t->x, e.x) << e.name;
        EXPECT_EQ(t->y, e.y) << e.name;
        EXPECT_EQ(t->width, 640);
        EXPECT_EQ(t->height, 480);
        EXPECT_FALSE(t->view.enabled);
    }
}

TEST(DisplayConfigShipped, Wall3x2WithBezels) {
    DisplayConfig c = load_ok("wall-3x2-bezel.json");
    EXPECT_EQ(c.canvas_width, 3 * 640 + 2 * 40);
    EXPECT_EQ(c.canvas_height, 2 * 480 + 40);
    ASSERT_EQ(c.tiles.size(), 6u);
    std::set<std::pair<int, int>> origins;
    for (const Tile& t : c.tiles) {
        EXPECT_EQ(t.width, 640) << t.name;
        EXPECT_EQ(t.height, 480) << t.name;
        EXPECT_FALSE(t.view.enabled);
        origins.insert({t.x, t.y});
    }
    std::set<std::pair<int, int>> expected = {{0, 0}, {680, 0}, {1360, 0}, {0, 520}, {680, 520}, {1360, 520}};
    EXPECT_EQ(origins, expected);
}

TEST(DisplayConfigShipped, Cylinder360) {
    DisplayConfig c = load_ok("cylinder-360.json");
    ASSERT_EQ(c.tiles.size(), 6u);
    EXPECT_EQ(c.canvas_width, 6 * 1600);
    EXPECT_EQ(c.canvas_height, 1200);
    for (int i = 0; i < 6; ++i) {
        const Tile& t = c.tiles[i];
        char name[16];
        std::snprintf(name, sizeof name, "yaw%03d", i * 60);
        EXPECT_EQ(t.name, name);
        EXPECT_EQ(t.x, i * 1600);
        EXPECT_EQ(t.y, 0);
        EXPECT_EQ(t.width, 1600);
        EXPECT_EQ(t.height, 1200);
        ASSERT_TRUE(t.view.enabled);
        EXPECT_EQ(t.view.yaw_deg, i * 60.0);
        EXPECT_EQ(t.view.pitch_deg, 0);
        EXPECT_EQ(t.view.roll_deg, 0);
        EXPECT_EQ(t.view.left_deg, -30);
        EXPECT_EQ(t.view.right_deg, 30);
        EXPECT_EQ(t.view.bottom_deg, -20);
        EXPECT_EQ(t.view.top_deg, 30);
    }
    // Six 60-degree frusta close the circle.
    double total = 0;
    for (const Tile& t : c.tiles) total += t.view.right_deg - t.view.left_deg;
    EXPECT_EQ(total, 360);
}

TEST(DisplayConfigShipped, Cave4) {
    DisplayConfig c = load_ok("cave-4.json");
    ASSERT_EQ(c.tiles.size(), 4u);
    // The file omits "canvas": the four walls side by side.
    EXPECT_EQ(c.canvas_width, 4 * 1024);
    EXPECT_EQ(c.canvas_height, 1024);
    struct {
        const char* name;
        double yaw, pitch;
    } expected[] = {{"front", 0, 0}, {"left", -90, 0}, {"right", 90, 0}, {"floor", 0, -90}};
    for (const auto& e : expected) {
        const Tile* t = c.find(e.name);
        ASSERT_NE(t, nullptr) << e.name;
        EXPECT_EQ(t->width, 1024);
        EXPECT_EQ(t->height, 1024);
        ASSERT_TRUE(t->view.enabled);
        EXPECT_EQ(t->view.yaw_deg, e.yaw) << e.name;
        EXPECT_EQ(t->view.pitch_deg, e.pitch) << e.name;
        EXPECT_EQ(t->view.roll_deg, 0);
        EXPECT_EQ(t->view.left_deg, -45);
        EXPECT_EQ(t->view.right_deg, 45);
        EXPECT_EQ(t->view.bottom_deg, -45);
        EXPECT_EQ(t->view.top_deg, 45);
    }
}

// ---- accepted input -----------------------------------------------------------------------

TEST(DisplayConfig, FindReturnsNullForUnknownTile) {
    DisplayConfig c = parse_ok(planar());
    ASSERT_NE(c.find("b"), nullptr);
    EXPECT_EQ(c.find("b")->x, 640);
    EXPECT_EQ(c.find("nope"), nullptr);
    EXPECT_EQ(c.find(""), nullptr);
}

TEST(DisplayConfig, OptionalFieldsTakeTheirDefaults) {
    DisplayConfig c = parse_ok(planar());
    EXPECT_EQ(c.description, "");
    EXPECT_FALSE(c.swap_barrier);
    EXPECT_TRUE(c.effects.empty());
    c = parse_ok(viewed("{}"));
    const TileView& v = c.tiles[0].view;
    EXPECT_TRUE(v.enabled);
    EXPECT_EQ(v.yaw_deg, 0);
    EXPECT_EQ(v.left_deg, -30);
    EXPECT_EQ(v.right_deg, 30);
    EXPECT_EQ(v.bottom_deg, -20);
    EXPECT_EQ(v.top_deg, 30);
}

TEST(DisplayConfig, AllFieldsAreRead) {
    DisplayConfig c = parse_ok(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})",
                                      R"(, "description": "two", "swap_barrier": true, "effects": ["snow", "shadows"])"));
    EXPECT_EQ(c.name, "wall");
    EXPECT_EQ(c.description, "two");
    EXPECT_TRUE(c.swap_barrier);
    EXPECT_EQ(c.effects, (std::vector<std::string>{"snow", "shadows"}));
    c = parse_ok(viewed(R"({"yaw": 12.5, "pitch": -3, "roll": 7, "left": -40, "right": 10, "bottom": -5, "top": 88.9})"));
    const TileView& v = c.tiles[0].view;
    EXPECT_EQ(v.yaw_deg, 12.5);
    EXPECT_EQ(v.pitch_deg, -3);
    EXPECT_EQ(v.roll_deg, 7);
    EXPECT_EQ(v.left_deg, -40);
    EXPECT_EQ(v.right_deg, 10);
    EXPECT_EQ(v.bottom_deg, -5);
    EXPECT_EQ(v.top_deg, 88.9);
}

TEST(DisplayConfig, EveryKnownEffectIsAccepted) {
    DisplayConfig c = parse_ok(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})",
                                      R"(, "effects": ["snow", "rain", "cover", "icicles", "shadows"])"));
    EXPECT_EQ(c.effects, known_display_effects());
}

TEST(DisplayConfig, IntegralFloatsAreIntegers) {
    DisplayConfig c = parse_ok(planar(R"({"name": "b", "x": 6.4e2, "y": 0.0, "width": 640.0, "height": 480})"));
    EXPECT_EQ(c.tiles[1].x, 640);
    EXPECT_EQ(c.tiles[1].width, 640);
}

TEST(DisplayConfig, ViewTilesWithoutCanvasAreLaidSideBySide) {
    DisplayConfig c = parse_ok(R"({"name": "ring", "tiles": [
        {"name": "a", "width": 800, "height": 600, "view": {"yaw": -40}},
        {"name": "b", "width": 1024, "height": 768, "view": {"yaw": 0}},
        {"name": "c", "width": 800, "height": 600, "view": {"yaw": 40}}]})");
    EXPECT_EQ(c.canvas_width, 800 + 1024 + 800);
    EXPECT_EQ(c.canvas_height, 768);
    EXPECT_EQ(c.tiles[0].x, 0);
    EXPECT_EQ(c.tiles[1].x, 800);
    EXPECT_EQ(c.tiles[2].x, 1824);
    EXPECT_EQ(c.tiles[2].y, 0);
}

TEST(DisplayConfig, ViewTilesKeepExplicitPositionsAndCanvas) {
    DisplayConfig c = parse_ok(R"({"name": "ring", "canvas": {"width": 4000, "height": 3000}, "tiles": [
        {"name": "a", "x": 10, "y": 20, "width": 800, "height": 600, "view": {}}]})");
    EXPECT_EQ(c.canvas_width, 4000);
    EXPECT_EQ(c.canvas_height, 3000);
    EXPECT_EQ(c.tiles[0].x, 10);
    EXPECT_EQ(c.tiles[0].y, 20);
}

TEST(DisplayConfig, FailureLeavesOutputUntouched) {
    DisplayConfig c;
    c.name = "before";
    std::string error;
    EXPECT_FALSE(parse_display_config("{", "x.json", c, error));
    EXPECT_EQ(c.name, "before");
}

// ---- validation rules, one per test, with the exact message ---------------------------------

TEST(DisplayConfigErrors, SyntaxErrorGivesLineAndColumn) {
    std::string e = error_of("{\n  \"name\": \"wall\",\n  \"tiles\" [\n");
    expect_contains(e, "wall.json: line 3, column 11: syntax error while parsing object separator");
    e = error_of("");
    expect_contains(e, "wall.json: line 1, column 1: syntax error while parsing value - unexpected end of input");
    e = error_of(planar() + "x");
    expect_contains(e, "wall.json: line 9, column 1: syntax error while parsing value");
    expect_contains(e, "expected end of input");
}

TEST(DisplayConfigErrors, HugeNumberIsAnOverflow) {
    // JSON cannot spell infinity; a number too large for a double is where "finite" bites.
    expect_contains(error_of(viewed(R"({"yaw": 1e400})")), "wall.json: line 1, column ");
    expect_contains(error_of(viewed(R"({"yaw": 1e400})")), ": number overflow parsing '1e400'");
}

TEST(DisplayConfigErrors, TopLevelMustBeAnObject) {
    EXPECT_EQ(error_of("[1, 2]"), "wall.json: the top level must be a JSON object, got an array");
    EXPECT_EQ(error_of("\"wall\""), "wall.json: the top level must be a JSON object, got \"wall\"");
}

TEST(DisplayConfigErrors, UnknownKeysAreNamed) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "widht": 640, "height": 480})")),
              "wall.json: tiles[1].widht: unknown key (did you mean \"width\"? known keys: name, x, y, width, height, view, screen, eye, stereo, machine, warp, blend, mpcdi, region)");
    expect_contains(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})", R"(, "efects": [])")),
                    "wall.json: efects: unknown key (did you mean \"effects\"?");
    expect_contains(error_of(viewed(R"({"yaw": 1, "fov": 60})")), "wall.json: tiles[0].view.fov: unknown key (known keys: yaw,");
    expect_contains(error_of(R"({"name": "w", "canvas": {"width": 1, "height": 1, "depth": 1}, "tiles": []})"),
                    "wall.json: canvas.depth: unknown key");
    // Keys that are not plain words are quoted and escaped.
    expect_contains(error_of(R"({"name": "w", "a b\u0001": 1})"), R"(wall.json: "a b\x01": unknown key)");
}

TEST(DisplayConfigErrors, DuplicateKeysAreErrors) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "width": 600})")),
              "wall.json: tiles[1].width: given twice in the same object (each key may appear once)");
}

TEST(DisplayConfigErrors, NonPositiveSizes) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": -5, "height": 480})")),
              "wall.json: tiles[1].width: must be a positive integer, got -5");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 0})")),
              "wall.json: tiles[1].height: must be a positive integer, got 0");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640.5, "height": 480})")),
              "wall.json: tiles[1].width: must be a positive integer, got 640.5");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": "640", "height": 480})")),
              "wall.json: tiles[1].width: must be a positive integer, got \"640\"");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": null, "height": 480})")),
              "wall.json: tiles[1].width: must be a positive integer, got null");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": [640], "height": 480})")),
              "wall.json: tiles[1].width: must be a positive integer, got an array");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 0, "height": 1}, "tiles": []})"),
              "wall.json: canvas.width: must be a positive integer, got 0");
}

TEST(DisplayConfigErrors, NegativePositions) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": -1, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1].x: must be a non-negative integer, got -1");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": true, "width": 640, "height": 480})")),
              "wall.json: tiles[1].y: must be a non-negative integer, got true");
}

TEST(DisplayConfigErrors, SizesAtMost16384) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 16385, "height": 480})")),
              "wall.json: tiles[1].width: must be at most 16384, got 16385");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 100, "height": 99999999999999999999}, "tiles": []})"),
              "wall.json: canvas.height: must be at most 16384, got 1e+20");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 18446744073709551615, "height": 1}, "tiles": []})"),
              "wall.json: canvas.width: must be at most 16384, got 18446744073709551615");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 1e300, "height": 1}, "tiles": []})"),
              "wall.json: canvas.width: must be at most 16384, got 1e+300");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": -1e300, "height": 1}, "tiles": []})"),
              "wall.json: canvas.width: must be a positive integer, got -1e+300");
    // 16384 itself is fine.
    parse_ok(R"({"name": "w", "canvas": {"width": 16384, "height": 16384},
                 "tiles": [{"name": "a", "x": 0, "y": 0, "width": 16384, "height": 16384}]})");
}

TEST(DisplayConfigErrors, ComputedCanvasAtMost16384) {
    EXPECT_EQ(error_of(R"({"name": "w", "tiles": [{"name": "a", "width": 10000, "height": 10, "view": {}},
                                                  {"name": "b", "width": 10000, "height": 20, "view": {}}]})"),
              "wall.json: canvas: missing, and the tiles side by side would make it 20000x20, wider than 16384; "
              "give \"canvas\" explicitly");
    expect_contains(error_of(R"({"name": "w", "canvas": {"width": 100, "height": 100}, "tiles": [
                       {"name": "a", "x": 16000, "width": 16000, "height": 10, "view": {}},
                       {"name": "b", "width": 100, "height": 20, "view": {}}]})"),
                    "wall.json: tiles[1].x: missing, and right of the previous tile it would be 32000, more than 16384");
}

TEST(DisplayConfigErrors, MissingRequiredKeys) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "height": 480})")), "wall.json: tiles[1].width: missing required key");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "y": 0, "width": 640, "height": 480})")), "wall.json: tiles[1].x: missing required key");
    EXPECT_EQ(error_of(planar(R"({"x": 640, "y": 0, "width": 640, "height": 480})")), "wall.json: tiles[1].name: missing required key");
    EXPECT_EQ(error_of(R"({"tiles": []})"), "wall.json: name: missing required key");
    EXPECT_EQ(error_of(R"({"name": "w"})"), "wall.json: tiles: missing required key");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 10}, "tiles": []})"), "wall.json: canvas.height: missing required key");
}

TEST(DisplayConfigErrors, AtLeastOneTile) {
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": {"width": 10, "height": 10}, "tiles": []})"),
              "wall.json: tiles: must list at least one tile");
    EXPECT_EQ(error_of(R"({"name": "w", "tiles": {}})"), "wall.json: tiles: must be an array of tiles, got an object");
    EXPECT_EQ(error_of(planar("7")), "wall.json: tiles[1]: must be an object, got 7");
}

TEST(DisplayConfigErrors, TileNamesAreUnique) {
    EXPECT_EQ(error_of(planar(R"({"name": "a", "x": 640, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1].name: \"a\" is used twice (also tiles[0].name)");
}

TEST(DisplayConfigErrors, NamesAreNonEmptyWords) {
    EXPECT_EQ(error_of(planar(R"({"name": "", "x": 640, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1].name: must not be empty");
    EXPECT_EQ(error_of(planar(R"({"name": "top left", "x": 640, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1].name: must contain only letters, digits, '_', '.' and '-', and start with a letter, a "
              "digit or '_' ([A-Za-z0-9_][A-Za-z0-9_.-]*: a name becomes a folder and a command-line word), got \"top left\"");
    // Names that would leave glcast run's --out folder, or read as an option.
    for (const char* name : {"..", ".", ".hidden", "-rf"})
        expect_contains(error_of(planar(std::string(R"({"name": ")") + name +
                                        R"(", "x": 640, "y": 0, "width": 640, "height": 480})")),
                        "wall.json: tiles[1].name: must contain only letters");
    EXPECT_EQ(error_of(planar(R"({"name": 3, "x": 640, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1].name: must be a string, got 3");
    expect_contains(error_of(R"({"name": "w/1", "tiles": []})"), "wall.json: name: must contain only letters");
    // Non-ASCII is escaped in the message.
    expect_contains(error_of(planar(R"({"name": "caf\u00e9", "x": 640, "y": 0, "width": 640, "height": 480})")),
                    R"(got "caf\xc3\xa9")");
    EXPECT_TRUE(is_valid_display_name("Tile_1.left-2"));
    EXPECT_FALSE(is_valid_display_name(""));
    EXPECT_FALSE(is_valid_display_name("a:b"));
    EXPECT_FALSE(is_valid_display_name(".."));
    EXPECT_FALSE(is_valid_display_name("-x"));
    EXPECT_TRUE(is_valid_display_name("_1"));
}

TEST(DisplayConfigErrors, OtherTypes) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})", R"(, "swap_barrier": 1)")),
              "wall.json: swap_barrier: must be true or false, got 1");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})", R"(, "description": ["x"])")),
              "wall.json: description: must be a string, got an array");
    EXPECT_EQ(error_of(R"({"name": "w", "canvas": [1, 2], "tiles": []})"), "wall.json: canvas: must be an object, got an array");
    EXPECT_EQ(error_of(viewed("true")), "wall.json: tiles[0].view: must be an object, got true");
}

TEST(DisplayConfigErrors, EffectsFromTheList) {
    const std::string tile = R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})";
    EXPECT_EQ(error_of(planar(tile, R"(, "effects": ["snow", "fog"])")),
              "wall.json: effects[1]: unknown effect \"fog\" (known effects: snow, rain, cover, icicles, shadows)");
    EXPECT_EQ(error_of(planar(tile, R"(, "effects": "snow")")), "wall.json: effects: must be an array of effect names, got \"snow\"");
    EXPECT_EQ(error_of(planar(tile, R"(, "effects": [1])")), "wall.json: effects[0]: must be a string (an effect name), got 1");
    EXPECT_EQ(error_of(planar(tile, R"(, "effects": ["snow", "snow"])")), "wall.json: effects[1]: \"snow\" is listed twice");
}

TEST(DisplayConfig, EffectParamsAreReadAsText) {
    const std::string tile = R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})";
    DisplayConfig c;
    std::string error;
    ASSERT_TRUE(parse_display_config(planar(tile, R"(, "effect_params": {"snow.particles": 500, "snow.spectral": false})"),
                                     "wall.json", c, error)) << error;
    EXPECT_EQ(c.effect_params, (std::vector<std::pair<std::string, std::string>>{{"snow.particles", "500"},
                                                                                 {"snow.spectral", "0"}}));
}

TEST(DisplayConfigErrors, EffectParamsAreChecked) {
    const std::string tile = R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})";
    EXPECT_EQ(error_of(planar(tile, R"(, "effect_params": [1])")),
              "wall.json: effect_params: must be an object of parameter names and values, got an array");
    EXPECT_EQ(error_of(planar(tile, R"(, "effect_params": {"snow.size": [2]})")),
              "wall.json: effect_params.snow.size: must be a number, a string or true/false, got an array");
    EXPECT_EQ(error_of(planar(tile, R"(, "effect_params": {"snow.particles": -1})")),
              "wall.json: effect_params.snow.particles: effect parameter snow.particles = -1 is out of range [0, 1e+06]");
    EXPECT_EQ(error_of(planar(tile, R"(, "effect_params": {"snow.particle": 1})")).rfind(
                  "wall.json: effect_params.snow.particle: unknown effect parameter \"snow.particle\"", 0),
              0u);
}

TEST(DisplayConfigErrors, PlanarTilesLieInsideTheCanvas) {
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 700, "y": 0, "width": 640, "height": 480})")),
              "wall.json: tiles[1]: does not fit on the 1280x480 canvas: x + width = 700 + 640 = 1340 > 1280");
    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 1, "width": 640, "height": 480})")),
              "wall.json: tiles[1]: does not fit on the 1280x480 canvas: y + height = 1 + 480 = 481 > 480");
    // View tiles place themselves freely (their rectangle only indexes canvas-wide effects).
    parse_ok(R"({"name": "w", "canvas": {"width": 100, "height": 100},
                 "tiles": [{"name": "a", "x": 50, "y": 50, "width": 800, "height": 600, "view": {}}]})");
}

TEST(DisplayConfigErrors, PlanarTilesNeedACanvas) {
    EXPECT_EQ(error_of(R"({"name": "w", "tiles": [{"name": "v", "width": 10, "height": 10, "view": {}},
                                                  {"name": "p", "x": 0, "y": 0, "width": 10, "height": 10}]})"),
              "wall.json: canvas: missing; it is required because tiles[1] has no \"view\" or \"screen\" (a planar tile is a rectangle of the canvas)");
}

TEST(DisplayConfigErrors, FrustumEdgesAreOrdered) {
    EXPECT_EQ(error_of(viewed(R"({"left": 30, "right": -30})")),
              "wall.json: tiles[0].view: left must be less than right, got left 30 and right -30");
    EXPECT_EQ(error_of(viewed(R"({"left": 10, "right": 10})")),
              "wall.json: tiles[0].view: left must be less than right, got left 10 and right 10");
    EXPECT_EQ(error_of(viewed(R"({"bottom": 40})")),  // top defaults to 30
              "wall.json: tiles[0].view: bottom must be less than top, got bottom 40 and top 30");
}

TEST(DisplayConfigErrors, FrustumEdgesWithin89Degrees) {
    EXPECT_EQ(error_of(viewed(R"({"left": -89})")), "wall.json: tiles[0].view.left: must be strictly between -89 and 89 degrees, got -89");
    EXPECT_EQ(error_of(viewed(R"({"top": 89})")), "wall.json: tiles[0].view.top: must be strictly between -89 and 89 degrees, got 89");
    EXPECT_EQ(error_of(viewed(R"({"right": 120.5})")),
              "wall.json: tiles[0].view.right: must be strictly between -89 and 89 degrees, got 120.5");
    parse_ok(viewed(R"({"left": -88.999, "right": 88.999, "bottom": -88.999, "top": 88.999})"));
}

TEST(DisplayConfigErrors, AnglesAreNumbers) {
    EXPECT_EQ(error_of(viewed(R"({"yaw": "90"})")), "wall.json: tiles[0].view.yaw: must be a number (degrees), got \"90\"");
    EXPECT_EQ(error_of(viewed(R"({"roll": null})")), "wall.json: tiles[0].view.roll: must be a number (degrees), got null");
    // Rotations themselves are not limited, only finite (see HugeNumberIsAnOverflow).
    DisplayConfig c = parse_ok(viewed(R"({"yaw": 720, "pitch": -90, "roll": 1e300})"));
    EXPECT_EQ(c.tiles[0].view.yaw_deg, 720);
    EXPECT_EQ(c.tiles[0].view.roll_deg, 1e300);
}

TEST(DisplayConfigErrors, DeepNestingIsRefused) {
    std::string deep = R"({"name": "w", "description": )" + std::string(1000, '[') + std::string(1000, ']') + "}";
    std::string path = "description";  // the 63rd array, inside the top-level object
    for (int i = 0; i < 62; ++i) path += "[0]";
    EXPECT_EQ(error_of(deep), "wall.json: " + path + ": nested deeper than 64 levels");
    // A million brackets: still just an error.
    error_of(std::string(1 << 20, '['));
}

TEST(DisplayConfigErrors, SizeCappedAt1MiB) {
    std::string big = planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})",
                             R"(, "description": ")" + std::string(1 << 20, 'x') + "\"");
    EXPECT_EQ(error_of(big), "wall.json: " + std::to_string(big.size()) +
                                 " bytes, more than the 1048576-byte (1 MiB) limit for a display config");
    std::string path = testing::TempDir() + "glcast_big_display_config.json";
    std::ofstream(path, std::ios::binary) << big;
    DisplayConfig c;
    std::string error;
    EXPECT_FALSE(load_display_config(path, c, error));
    EXPECT_EQ(error, path + ": larger than the 1048576-byte (1 MiB) limit for a display config");
    std::remove(path.c_str());
}

TEST(DisplayConfigErrors, UnreadableFiles) {
    DisplayConfig c;
    std::string error;
    EXPECT_FALSE(load_display_config("/nonexistent/wall.json", c, error));
    EXPECT_EQ(error, "/nonexistent/wall.json: cannot open: No such file or directory");
    EXPECT_FALSE(load_display_config(std::string(GLCAST_SOURCE_DIR) + "/display_configs", c, error));
    expect_contains(error, "/display_configs: is a directory, not a regular file");
    // A FIFO named as a config: refused at once (it hung the reader until something wrote to it).
    const std::string fifo = "/tmp/glcast-config-fifo-" + std::to_string(getpid());
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    EXPECT_FALSE(load_display_config(fifo, c, error));
    EXPECT_EQ(error, fifo + ": is a FIFO, not a regular file");
    ::unlink(fifo.c_str());
}

// ---- never crash ------------------------------------------------------------------------------

TEST(DisplayConfigRobustness, RandomBytes) {
    std::mt19937 rng(1234);
    for (int i = 0; i < 500; ++i) {
        std::string text(rng() % 200, '\0');
        for (char& ch : text) ch = static_cast<char>(rng());
        DisplayConfig c;
        std::string error;
        EXPECT_FALSE(parse_display_config(text, "random.json", c, error));
        EXPECT_EQ(error.rfind("random.json: ", 0), 0u) << error;
        for (unsigned char ch : error) EXPECT_TRUE(ch >= 0x20 && ch < 0x7f) << "unprintable byte in: " << error;
    }
}

// 2000 random mutations of a valid config: each parse only returns true or false, errors name the
// origin, and whatever is accepted satisfies every rule.
TEST(DisplayConfigRobustness, MutatedConfigs) {
    std::ifstream in(config_path("cylinder-360.json"), std::ios::binary);
    std::string base((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string planar_text = planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480})",
                                     R"(, "swap_barrier": true, "effects": ["snow"])");
    ASSERT_FALSE(base.empty());
    const char* tokens[] = {"-",  "0",     "-5",    "1e400", "1e20", "99999999999999999999", "16385", "89", "-89",
                            "\"", "\\",    "{",     "}",     "[",    "]",                    ",",     ":",  "null",
                            "[]", "{}",    "true",  "\"x\"", "\xff", "\"view\": {}",         "\"name\": \"a\"",
                            "0.5", "\"effects\": [\"rain\"]", "\"canvas\": {\"width\": 10, \"height\": 10}"};
    std::mt19937 rng(42);
    int accepted = 0;
    for (int i = 0; i < 2000; ++i) {
        std::string text = (i % 2) ? base : planar_text;
        int edits = 1 + static_cast<int>(rng() % 3);
        for (int k = 0; k < edits && !text.empty(); ++k) {
            size_t pos = rng() % text.size();
            switch (rng() % 6) {
            case 0: text[pos] = static_cast<char>(rng()); break;                                    // any byte
            case 1: text.erase(pos, 1 + rng() % 20); break;                                          // delete
            case 2: text.insert(pos, tokens[rng() % (sizeof tokens / sizeof *tokens)]); break;        // token
            case 3: {                                                                                 // duplicate a range
                size_t len = std::min<size_t>(1 + rng() % 80, text.size() - pos);
                text.insert(rng() % text.size(), text.substr(pos, len));
                break;
            }
            case 4: {  // replace a digit run with a token
                size_t d = text.find_first_of("0123456789", pos);
                if (d == std::string::npos) break;
                size_t e = text.find_first_not_of("0123456789", d);
                text.replace(d, (e == std::string::npos ? text.size() : e) - d, tokens[rng() % 9]);
                break;
            }
            case 5: text.resize(pos); break;  // truncate
            }
        }
        DisplayConfig c;
        std::string error;
        bool ok = parse_display_config(text, "fuzz.json", c, error);
        if (!ok) {
            EXPECT_EQ(error.rfind("fuzz.json: ", 0), 0u) << error;
            continue;
        }
        ++accepted;
        ASSERT_FALSE(c.tiles.empty());
        EXPECT_TRUE(c.canvas_width > 0 && c.canvas_width <= 16384);
        EXPECT_TRUE(c.canvas_height > 0 && c.canvas_height <= 16384);
        std::set<std::string> names;
        for (const Tile& t : c.tiles) {
            EXPECT_TRUE(is_valid_display_name(t.name));
            EXPECT_TRUE(names.insert(t.name).second);
            EXPECT_TRUE(t.width > 0 && t.width <= 16384 && t.height > 0 && t.height <= 16384);
            EXPECT_TRUE(t.x >= 0 && t.y >= 0);
            if (!t.view.enabled) {
                EXPECT_LE(t.x + t.width, c.canvas_width);
                EXPECT_LE(t.y + t.height, c.canvas_height);
            } else {
                EXPECT_LT(t.view.left_deg, t.view.right_deg);
                EXPECT_LT(t.view.bottom_deg, t.view.top_deg);
                for (double a : {t.view.left_deg, t.view.right_deg, t.view.bottom_deg, t.view.top_deg})
                    EXPECT_TRUE(a > -89 && a < 89);
                for (double a : {t.view.yaw_deg, t.view.pitch_deg, t.view.roll_deg}) EXPECT_TRUE(std::isfinite(a));
            }
        }
        for (const std::string& e : c.effects) {
            const auto& known = known_display_effects();
            EXPECT_NE(std::find(known.begin(), known.end(), e), known.end());
        }
    }
    // The mutations must not be so wild that nothing parses: some survive and get checked.
    EXPECT_GT(accepted, 50);
}

TEST(DisplayConfigProgramProjection, ReadAndChecked) {
    glcast::slave::DisplayConfig c;
    std::string error;
    ASSERT_TRUE(glcast::slave::load_display_config(std::string(GLCAST_SOURCE_DIR) + "/tests/configs/cylinder-360-shader.json",
                                                   c, error)) << error;
    EXPECT_TRUE(c.program_projection.given);
    EXPECT_NEAR(c.program_projection.fov_y_deg, 46.826, 0.001);
    EXPECT_DOUBLE_EQ(c.program_projection.near, 0.5);
    const std::string bad = R"({"name": "x", "canvas": {"width": 10, "height": 10},
        "tiles": [{"name": "a", "x": 0, "y": 0, "width": 10, "height": 10}],
        "program_projection": {"fov_y": 200, "near": 1, "far": 2}})";
    EXPECT_FALSE(glcast::slave::parse_display_config(bad, "p.json", c, error));
    EXPECT_NE(error.find("p.json: program_projection.fov_y: must be in (0, 179) degrees"), std::string::npos) << error;
}

// A wall of several machines: which machine shows a tile, where they reach the master, its keys.
TEST(DisplayConfigMachines, MachineMasterAndKeys) {
    const std::string tile = R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "machine": "display-2"})";
    DisplayConfig c = parse_ok(planar(tile, R"(, "master": {"address": "10.0.0.1", "port": 7000}, "keys": "keys")"));
    EXPECT_EQ(c.tiles[1].machine, "display-2");
    EXPECT_TRUE(c.tiles[0].machine.empty());
    EXPECT_TRUE(c.master.given);
    EXPECT_EQ(c.master.address, "10.0.0.1");
    EXPECT_EQ(c.master.port, 7000);
    EXPECT_EQ(c.keys, "keys");
    EXPECT_EQ(parse_ok(planar(tile, R"(, "master": {"address": "wall-master.local"})")).master.port, 5555);

    EXPECT_EQ(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "machine": "a b"})")),
              R"(wall.json: tiles[1].machine: must be a machine name of letters, digits, '_', '.' and '-', got "a b")");
    EXPECT_EQ(error_of(planar(tile, R"(, "master": {"port": 7000})")), "wall.json: master.address: missing required key");
    EXPECT_EQ(error_of(planar(tile, R"(, "master": {"address": "x;rm"})")),
              R"(wall.json: master.address: must be a host name or IP address, got "x;rm")");
    EXPECT_EQ(error_of(planar(tile, R"(, "master": {"address": "h", "port": 65533})")),
              "wall.json: master.port: must be an integer from 1 to 65532 (it and the next three ports are used), got 65533");
    EXPECT_EQ(error_of(planar(tile, R"(, "master": {"address": "h", "prot": 1})")).substr(0, 48),
              "wall.json: master.prot: unknown key (did you mea");
    EXPECT_EQ(error_of(planar(tile, R"(, "keys": 5)")), "wall.json: keys: must be the path of a folder of keys, got 5");
}

TEST(DisplayConfigErrors, ProjectorMapsComeAsThePlainPairOrOneMpcdiRegion) {
    expect_contains(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "warp": "w.pfm",
                                         "mpcdi": "m.mpcdi", "region": "b"})")),
                    "has \"mpcdi\" and \"warp\" or \"blend\": the MPCDI file holds both, give one");
    expect_contains(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "region": "b"})")),
                    "\"mpcdi\" and \"region\" come together");
    expect_contains(error_of(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480, "blend": 3})")),
                    "tiles[1].blend: must be a file name (a non-empty string), got 3");
    DisplayConfig c;
    std::string error;
    ASSERT_TRUE(parse_display_config(planar(R"({"name": "b", "x": 640, "y": 0, "width": 640, "height": 480,
                                                "warp": "b.pfm", "blend": "b.png"})"), "wall.json", c, error)) << error;
    EXPECT_EQ(c.tiles[1].warp, "b.pfm");
    EXPECT_EQ(c.tiles[1].blend, "b.png");
}
