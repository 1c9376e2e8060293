// The passes an operator switches while a program runs (slave/live_effects.h): requests checked
// before anything changes, and the control channel's words read back only when well formed.
#include <gtest/gtest.h>

#include "slave/live_effects.h"

using glcast::slave::LiveEffects;
namespace effects = glcast::slave::effects;

TEST(LiveEffects, RequestsSwitchPassesAndSetParameters) {
    effects::EffectsSettings started;
    std::string error;
    ASSERT_TRUE(started.enable("shadows", error));
    LiveEffects e = LiveEffects::from(started);
    EXPECT_EQ(e.enabled_list(), "shadows");
    ASSERT_TRUE(e.change("effects +snow -shadows cover", error)) << error;
    EXPECT_EQ(e.enabled_list(), "snow,cover");
    ASSERT_TRUE(e.change("param snow.fall_speed=2.5 snow.particles=100", error)) << error;
    const effects::EffectsSettings now = e.applied_to(started);
    EXPECT_TRUE(now.snow && now.cover && !now.shadows);
    EXPECT_DOUBLE_EQ(now.params.number("snow.fall_speed"), 2.5);
    EXPECT_DOUBLE_EQ(now.params.number("snow.particles"), 100);
}

TEST(LiveEffects, BadRequestsChangeNothingAndSayWhatExists) {
    LiveEffects e;
    std::string error;
    ASSERT_TRUE(e.change("effects +snow", error));
    const std::string before = e.words();
    EXPECT_FALSE(e.change("effects +snow +snwo", error));
    EXPECT_NE(error.find("unknown effect \"snwo\""), std::string::npos) << error;
    EXPECT_NE(error.find("snow, rain, cover, icicles, shadows"), std::string::npos) << error;
    EXPECT_FALSE(e.change("param snow.fall_speed=1 snow.fall_sped=2", error));
    EXPECT_NE(error.find("did you mean \"snow.fall_speed\""), std::string::npos) << error;
    EXPECT_FALSE(e.change("param snow.fall_speed=100000", error));
    EXPECT_NE(error.find("out of range"), std::string::npos) << error;
    EXPECT_FALSE(e.change("param snow.fall_speed", error));
    EXPECT_FALSE(e.change("effects", error));
    EXPECT_FALSE(e.change("reboot now", error));
    EXPECT_NE(error.find("requests: effects"), std::string::npos) << error;
    for (const effects::ParamSpec& s : effects::all_param_specs())
        if (s.text) {
            EXPECT_FALSE(e.change("param " + s.name + "=/etc/passwd", error)) << s.name;
            EXPECT_NE(error.find("not live"), std::string::npos) << error;
        }
    EXPECT_EQ(e.words(), before);
}

TEST(LiveEffects, WordsRoundTripAndMalformedOnesAreRefused) {
    LiveEffects e;
    std::string error;
    ASSERT_TRUE(e.change("effects +snow +icicles", error));
    ASSERT_TRUE(e.change("param snow.wind_x=-3", error));
    e.version = 7, e.frame = 1234;
    LiveEffects back;
    ASSERT_TRUE(LiveEffects::parse(e.words(), back)) << e.words();
    EXPECT_EQ(back.words(), e.words());
    EXPECT_EQ(back.version, 7u);
    EXPECT_EQ(back.frame, 1234u);
    for (const char* bad : {"", "EFFECTS", "EFFECTS 1 2", "EFFECTS x 2 snow", "EFFECTS 1 2 snow,fire", "EFFECTS 1 2 snow,,cover",
                            "EFFECTS 1 2 none snow.wind_x=1e9", "EFFECTS 1 2 none nothing=1", "GO 1 2 snow"})
        EXPECT_FALSE(LiveEffects::parse(bad, back)) << bad;
    ASSERT_TRUE(LiveEffects::parse("EFFECTS 3 0 none", back));
    EXPECT_EQ(back.enabled_list(), "none");
}
