// Screens in metres, eyes and the viewer in display configs (display_configs/immersive_config.h):
// the shipped CAVE in metres loads with its corners, and every rule gives its message; head poses
// (display_configs/head_poses.h) and the size of a stereo tile's eyes (slave/stereo.h).
#include <gtest/gtest.h>

#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

#include "display_configs/display_config.h"
#include "display_configs/head_poses.h"
#include "slave/stereo.h"

using namespace glcast::slave;

namespace {

std::string with_tile(const std::string& tile, const std::string& extra = "") {
    return R"({"name": "room", "tiles": [)" + tile + "]" + extra + "}";
}

std::string screen_tile(const std::string& screen, const std::string& more = "") {
    return R"({"name": "s", "width": 100, "height": 100, "screen": )" + screen + more + "}";
}

const char* const kFront = R"({"bottom_left": [-1.5, -1.5, -1.5], "bottom_right": [1.5, -1.5, -1.5], "top_left": [-1.5, 1.5, -1.5]})";

std::string error_of(const std::string& text) {
    DisplayConfig c;
    std::string error;
    EXPECT_FALSE(parse_display_config(text, "room.json", c, error)) << "accepted:\n" << text;
    return error;
}

DisplayConfig parse_ok(const std::string& text) {
    DisplayConfig c;
    std::string error;
    EXPECT_TRUE(parse_display_config(text, "room.json", c, error)) << error << "\n" << text;
    return c;
}

}  // namespace

TEST(ImmersiveConfig, TheShippedCaveInMetres) {
    DisplayConfig c;
    std::string error;
    ASSERT_TRUE(load_display_config(std::string(GLCAST_SOURCE_DIR) + "/display_configs/cave-4-metres.json", c, error)) << error;
    ASSERT_EQ(c.tiles.size(), 4u);
    EXPECT_EQ(c.canvas_width, 4096);
    for (const Tile& t : c.tiles) {
        EXPECT_TRUE(t.view.enabled && t.view.screen) << t.name;
        EXPECT_EQ(t.eye, TileEye::centre);
    }
    const Tile* floor = c.find("floor");
    ASSERT_NE(floor, nullptr);
    EXPECT_EQ(floor->view.top_left, (std::array<double, 3>{-1.5, -1.5, -1.5}));
    EXPECT_EQ(c.viewer.eye_separation, 0.064);
    EXPECT_EQ(c.viewer.units_per_metre, 1);
}

TEST(ImmersiveConfig, EyesStereoAndTheViewerAreRead) {
    const DisplayConfig c = parse_ok(with_tile(screen_tile(kFront, R"(, "eye": "right")") + "," +
                                                   R"({"name": "t", "width": 100, "height": 100, "screen": )" + kFront +
                                                   R"(, "stereo": "side-by-side"})",
                                               R"(, "viewer": {"position": [0.1, 0.2, 0.3], "eye_separation": 0.07, "units_per_metre": 100})"));
    EXPECT_EQ(c.tiles[0].eye, TileEye::right);
    EXPECT_EQ(c.tiles[1].stereo, Stereo::side_by_side);
    EXPECT_EQ(c.viewer.position, (std::array<double, 3>{0.1, 0.2, 0.3}));
    EXPECT_EQ(c.viewer.eye_separation, 0.07);
    EXPECT_EQ(c.viewer.units_per_metre, 100);
}

TEST(ImmersiveConfig, BadScreensAreRefusedWithWhatIsWrong) {
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0, -1], "bottom_right": [1, 0, -1]})"))),
              "room.json: tiles[0].screen.top_left: missing required key");
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0], "bottom_right": [1, 0, -1], "top_left": [0, 1, -1]})"))),
              "room.json: tiles[0].screen.bottom_left: must be [x, y, z] in metres, got an array");
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0, 1e9], "bottom_right": [1, 0, -1], "top_left": [0, 1, -1]})"))),
              "room.json: tiles[0].screen.bottom_left[2]: must be a number of metres within +-10000, got 1000000000");
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0, -1], "bottom_right": [1, 0, -1], "top_left": [0.2, 1, -1]})"))),
              "room.json: tiles[0].screen: the corners must make a rectangle: bottom_left->bottom_right and "
              "bottom_left->top_left meet at 78.69 degrees, not 90");
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0, -1], "bottom_right": [0, 0, -1], "top_left": [0, 1, -1]})"))),
              "room.json: tiles[0].screen: the screen is 0 m wide and 1 m high: both must be at least a millimetre");
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [0, 0, -1], "bottom_right": [1, 0, -1], "top_left": [0, 1, -1], "up": 1})"))),
              "room.json: tiles[0].screen.up: unknown key (known keys: bottom_left, bottom_right, top_left)");
    // The corners turned the other way: the screen faces away from the viewer.
    EXPECT_EQ(error_of(with_tile(screen_tile(R"({"bottom_left": [1.5, -1.5, -1.5], "bottom_right": [-1.5, -1.5, -1.5], "top_left": [1.5, 1.5, -1.5]})"))),
              "room.json: tiles[0].screen: the viewer's position [0, 0, 0] is behind this screen (its front is where "
              "bottom_left->bottom_right x bottom_left->top_left points): turn the corners or move the viewer");
    EXPECT_EQ(error_of(with_tile(R"({"name": "s", "width": 100, "height": 100, "view": {"yaw": 0}, "screen": )" + std::string(kFront) + "}")),
              "room.json: tiles[0]: has both \"view\" (angles) and \"screen\" (corners in metres): give one");
}

TEST(ImmersiveConfig, BadEyesAndViewersAreRefused) {
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront, R"(, "eye": "centre")"))),
              "room.json: tiles[0].eye: must be \"left\" or \"right\", got \"centre\"");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront, R"(, "stereo": "interlaced")"))),
              "room.json: tiles[0].stereo: must be \"quad-buffer\", \"side-by-side\", \"top-bottom\" or \"anaglyph\", got \"interlaced\"");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront, R"(, "stereo": "anaglyph", "eye": "left")"))),
              "room.json: tiles[0]: has both \"eye\" (one eye per output) and \"stereo\" (both eyes in one output): give one");
    EXPECT_EQ(error_of(R"({"name": "room", "canvas": {"width": 100, "height": 100}, "tiles": [{"name": "p", "x": 0, "y": 0, "width": 100, "height": 100, "eye": "left"}]})"),
              "room.json: tiles[0].eye: needs a \"view\" or a \"screen\": a planar tile has no camera to move to an eye");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront), R"(, "viewer": {"eye_separation": -0.1})")),
              "room.json: viewer.eye_separation: must be a number of metres from 0 to 1, got -0.1");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront), R"(, "viewer": {"units_per_metre": 0})")),
              "room.json: viewer.units_per_metre: must be a number from 1e-6 to 1e6, got 0");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront), R"(, "viewer": {"position": [0, 0, -1.5]})")),
              "room.json: tiles[0].screen: the viewer's position [0, 0, -1.5] is on this screen's plane (its front is where "
              "bottom_left->bottom_right x bottom_left->top_left points): turn the corners or move the viewer");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront), R"(, "viewer": {"position": [0, 0, "x"]})")),
              "room.json: viewer.position[2]: must be a number of metres within +-10000, got \"x\"");
    EXPECT_EQ(error_of(with_tile(screen_tile(kFront), R"(, "viewer": {"head": 1})")),
              "room.json: viewer.head: unknown key (known keys: position, eye_separation, units_per_metre, tracker)");
}

// ---- head poses (display_configs/head_poses.h) ---------------------------------------------

TEST(HeadPoses, APoseIsRead) {
    HeadPose p;
    uint64_t frame = 0;
    double time = 0;
    std::string error;
    ASSERT_TRUE(parse_head_pose(R"({"frame": 12, "time": 3.5, "position": [0.1, 1.6, -0.2], "orientation": [0.7071068, 0, 0.7071068, 0]})",
                                p, &frame, &time, error)) << error;
    EXPECT_EQ(frame, 12u);
    EXPECT_EQ(time, 3.5);
    EXPECT_EQ(p.position, glm::dvec3(0.1, 1.6, -0.2));
    // A quarter turn to the left about y: the head's right axis points towards the viewer (+z).
    const glm::dvec3 right = p.orientation * glm::dvec3(1, 0, 0);
    EXPECT_NEAR(right.z, -1, 1e-6);
}

TEST(HeadPoses, CraftedPosesAreRefusedWithWhatIsWrong) {
    const std::pair<std::string, std::string> cases[] = {
        {R"({"position": [0, 0], "orientation": [1, 0, 0, 0]})", "pose: position: must be [x, y, z], metres within +-10000, got an array"},
        {R"({"position": [0, 0, 1e300], "orientation": [1, 0, 0, 0]})", "pose: position: must be [x, y, z], metres within +-10000, got an array"},
        {R"({"position": [0, 0, NaN], "orientation": [1, 0, 0, 0]})", "not JSON"},
        {R"({"position": [0, 0, 0], "orientation": [2, 0, 0, 0]})", "pose: orientation: must be a unit quaternion, its length is 2"},
        {R"({"position": [0, 0, 0], "orientation": [0, 0, 0, 0]})", "pose: orientation: must be a unit quaternion, its length is 0"},
        {R"({"position": [0, 0, 0]})", "pose: orientation: must be a quaternion [w, x, y, z], got nothing"},
        {R"({"position": [0, 0, 0], "orientation": [1, 0, 0, 0], "scale": 2})",
         "pose: scale: unknown key (known keys: frame, time, position, orientation, eye_separation)"},
        {R"({"position": [0, 0, 0], "orientation": [1, 0, 0, 0], "eye_separation": 2})",
         "pose: eye_separation: must be a number of metres from 0 to 1, got 2"},
        {R"([1, 2, 3])", "pose: must be a JSON object, got an array"},
        {R"({"position": [0, 0, 0], "orientation": [1, 0, 0, 0], "time": "now"})", "pose: time: must be seconds, got \"now\""},
        {"", "not JSON"},
        {std::string(5000, ' '), "5000 bytes, more than the 4096 a pose may have"},
    };
    for (const auto& [text, message] : cases) {
        HeadPose p;
        p.position = {7, 7, 7};
        std::string error;
        EXPECT_FALSE(parse_head_pose(text, p, nullptr, nullptr, error)) << text;
        EXPECT_EQ(error, message) << text;
        EXPECT_EQ(p.position, glm::dvec3(7, 7, 7)) << "a refused pose changed the output";
    }
}

TEST(HeadPoses, ATrackHoldsEachPoseFromItsFrameOn) {
    const std::string path = ::testing::TempDir() + "/poses.jsonl";
    {
        std::FILE* f = std::fopen(path.c_str(), "w");
        std::fputs("# a recorded head\n{\"frame\": 2, \"position\": [1, 0, 0], \"orientation\": [1, 0, 0, 0]}\n\n"
                   "{\"frame\": 5, \"position\": [2, 0, 0], \"orientation\": [1, 0, 0, 0]}\n", f);
        std::fclose(f);
    }
    HeadPoseTrack track;
    std::string error;
    ASSERT_TRUE(track.load(path, error)) << error;
    EXPECT_EQ(track.size(), 2u);
    EXPECT_EQ(track.at(0), nullptr);
    EXPECT_EQ(track.at(1), nullptr);
    EXPECT_EQ(track.at(2)->position.x, 1);
    EXPECT_EQ(track.at(4)->position.x, 1);
    EXPECT_EQ(track.at(5)->position.x, 2);
    EXPECT_EQ(track.at(1000)->position.x, 2);
}

TEST(HeadPoses, ABadTrackIsRefusedWholeWithItsLine) {
    const std::string path = ::testing::TempDir() + "/bad-poses.jsonl";
    auto refused = [&](const std::string& text) {
        std::FILE* f = std::fopen(path.c_str(), "w");
        std::fputs(text.c_str(), f);
        std::fclose(f);
        HeadPoseTrack track;
        std::string error;
        EXPECT_FALSE(track.load(path, error)) << text;
        EXPECT_EQ(track.size(), 0u);
        return error.substr(path.size());
    };
    EXPECT_EQ(refused("{\"frame\": 5, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}\n"
                      "{\"frame\": 5, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}\n"),
              ": line 2: frame 5 does not come after the previous line's 5");
    EXPECT_EQ(refused("{\"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}\n"),
              ": line 1: pose: frame: must be a frame number (0 or more), got nothing");
    EXPECT_EQ(refused("{\"frame\": -1, \"position\": [0, 0, 0], \"orientation\": [1, 0, 0, 0]}\n"),
              ": line 1: pose: frame: must be a frame number (0 or more), got -1");
    HeadPoseTrack track;
    std::string error;
    EXPECT_FALSE(track.load("/nonexistent/poses.jsonl", error));
    EXPECT_EQ(error, "/nonexistent/poses.jsonl: cannot open");
}

// A FIFO named as a track would hang the reader; a file of one endless line would be read whole
// into memory before any limit applied.
TEST(HeadPoses, AFifoOrAnOversizedTrackIsRefusedBeforeItIsRead) {
    const std::string fifo = ::testing::TempDir() + "/poses.fifo";
    ::unlink(fifo.c_str());
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    HeadPoseTrack track;
    std::string error;
    EXPECT_FALSE(track.load(fifo, error));
    EXPECT_EQ(error, fifo + ": is a FIFO, not a regular file");
    ::unlink(fifo.c_str());
    const std::string big = ::testing::TempDir() + "/poses-big.jsonl";
    {
        std::FILE* f = std::fopen(big.c_str(), "w");
        ASSERT_NE(f, nullptr);
        ASSERT_EQ(::ftruncate(::fileno(f), off_t(kMaxPoseTrackBytes) + 1), 0);  // one line of NULs, sparse
        std::fclose(f);
    }
    EXPECT_FALSE(track.load(big, error));
    EXPECT_EQ(error, big + ": larger than the 64 MiB a pose track may have");
    EXPECT_EQ(track.size(), 0u);
    ::unlink(big.c_str());
}

// ---- the eyes' size (slave/stereo.h; their composition: immersive_stereo_disparity) ---------

TEST(StereoEyes, EachModeRendersTheEyesAtItsSize) {
    int w = 0, h = 0;
    eye_size(StereoMode::side_by_side, 1921, 1080, w, h);
    EXPECT_EQ(w, 960);
    EXPECT_EQ(h, 1080);
    eye_size(StereoMode::top_bottom, 1920, 1080, w, h);
    EXPECT_EQ(w, 1920);
    EXPECT_EQ(h, 540);
    eye_size(StereoMode::anaglyph, 1920, 1080, w, h);
    EXPECT_EQ(w, 1920);
    EXPECT_EQ(h, 1080);
    eye_size(StereoMode::side_by_side, 1, 1, w, h);
    EXPECT_EQ(w, 1);
}
