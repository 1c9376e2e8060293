// The process's configuration without a driver or a socket: every GLCAST_* variable of the
// command checked with its name in the error (common/environment.h), and the one place the
// wall's channels and ports come from (net/wall_endpoints.h).
#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "common/environment.h"
#include "net/wall_endpoints.h"

namespace glcast {
namespace {

// Sets one variable for the test's scope.
class ScopedVariable {
public:
    ScopedVariable(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        setenv(name, value, 1);
    }
    ~ScopedVariable() {
        if (had_) setenv(name_, old_.c_str(), 1);
        else unsetenv(name_);
    }

private:
    const char* name_;
    std::string old_;
    bool had_ = false;
};

std::string environment_error() {
    try {
        (void)read_environment();
    } catch (const EnvironmentError& e) {
        return e.what();
    }
    return "";
}

TEST(Environment, DefaultsWhenNothingIsSet) {
    for (const char* name : {"GLCAST_CATCH_UP_MB", "GLCAST_INSECURE", "GLCAST_EGL_CONFIG_ID", "GLCAST_MACHINE"})
        unsetenv(name);
    const Environment e = read_environment();
    EXPECT_EQ(e.catch_up_bytes, uint64_t(2048) << 20);
    EXPECT_FALSE(e.insecure);
    EXPECT_EQ(e.egl_config_id, 0u);
    EXPECT_EQ(e.machine, "");
}

TEST(Environment, GoodValuesAreTaken) {
    ScopedVariable mb("GLCAST_CATCH_UP_MB", "8"), insecure("GLCAST_INSECURE", "1"), id("GLCAST_EGL_CONFIG_ID", "12"),
        machine("GLCAST_MACHINE", "display-3");
    const Environment e = read_environment();
    EXPECT_EQ(e.catch_up_bytes, uint64_t(8) << 20);
    EXPECT_TRUE(e.insecure);
    EXPECT_EQ(e.egl_config_id, 12u);
    EXPECT_EQ(e.machine, "display-3");
}

TEST(Environment, EveryBadValueIsRefusedWithItsName) {
    const struct {
        const char *name, *value;
    } bad[] = {{"GLCAST_CATCH_UP_MB", "0"},       {"GLCAST_CATCH_UP_MB", "lots"},  {"GLCAST_CATCH_UP_MB", "-5"},
               {"GLCAST_CATCH_UP_MB", "1048577"}, {"GLCAST_CATCH_UP_MB", "8 "},    {"GLCAST_CATCH_UP_MB", "+8"},
               {"GLCAST_INSECURE", "yes"},        {"GLCAST_INSECURE", "2"},        {"GLCAST_EGL_CONFIG_ID", "x"},
               {"GLCAST_EGL_CONFIG_ID", "99999999999"}};
    for (const auto& b : bad) {
        ScopedVariable v(b.name, b.value);
        const std::string error = environment_error();
        EXPECT_NE(error.find(std::string(b.name) + "=" + b.value), std::string::npos) << b.name << "=" << b.value
                                                                                     << ": " << error;
    }
}

TEST(Environment, TheShimParsersShareTheRules) {
    ScopedVariable v("GLCAST_TEST_NUMBER", "70");
    EXPECT_EQ(env_uint("GLCAST_TEST_NUMBER", 0, 100, 5), 70u);
    EXPECT_THROW(env_uint("GLCAST_TEST_NUMBER", 0, 69, 5), EnvironmentError);
    EXPECT_EQ(env_uint("GLCAST_TEST_UNSET_NUMBER", 0, 100, 5), 5u);
    EXPECT_THROW(env_flag("GLCAST_TEST_NUMBER", false), EnvironmentError);
}

TEST(WallEndpoints, TcpChannelsAreTheNextThreePorts) {
    const net::WallEndpoints e = net::wall_endpoints("tcp://*:5555");
    EXPECT_EQ(e.stream, "tcp://*:5555");
    EXPECT_EQ(e.journal, "tcp://*:5556");
    EXPECT_EQ(e.keeper, "tcp://*:5557");
    EXPECT_EQ(e.control, "tcp://*:5558");
    EXPECT_TRUE(e.reachable);
    EXPECT_EQ(net::connectable(e.journal), "tcp://127.0.0.1:5556");
    const net::WallEndpoints at = net::wall_endpoints_at("10.0.0.2", 7000);
    EXPECT_EQ(at.control, "tcp://10.0.0.2:7003");
    EXPECT_EQ(net::wall_channel("tcp://[::1]:9000", net::WallChannel::keeper), "tcp://[::1]:9002");
}

TEST(WallEndpoints, MulticastSideChannelsAreTcpOnTheInterface) {
    const net::WallEndpoints e = net::wall_endpoints("epgm://eth0;239.192.1.1:5555");
    EXPECT_EQ(e.stream, "epgm://eth0;239.192.1.1:5555");
    EXPECT_EQ(e.journal, "tcp://eth0:5556");
    EXPECT_EQ(e.control, "tcp://eth0:5558");
}

TEST(WallEndpoints, IpcChannelsAreSiblingPaths) {
    const net::WallEndpoints e = net::wall_endpoints("ipc:///tmp/wall/stream");
    EXPECT_EQ(e.journal, "ipc:///tmp/wall/stream-journal");
    EXPECT_EQ(e.keeper, "ipc:///tmp/wall/stream-keeper");
    EXPECT_EQ(e.control, "ipc:///tmp/wall/stream-control");
    EXPECT_FALSE(e.reachable);
}

TEST(WallEndpoints, PortsThatLeaveNoRoomOrNoPortAreRefusedByName) {
    for (const char* bad : {"tcp://*:65533", "tcp://*:0", "tcp://*", "tcp://*:55x", "tcp://host:1234567",
                            "udp://*:5555", "epgm://239.192.1.1:5555"}) {
        try {
            (void)net::wall_endpoints(bad);
            ADD_FAILURE() << bad << " was taken";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(net::wall_endpoints("tcp://*:65532").control, "tcp://*:65535");
}

}  // namespace
}  // namespace glcast
