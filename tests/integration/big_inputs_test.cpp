// Inputs whose cost is only known once they are read, and files that are not what they say: a
// projector's blend map whose PNG is small but whose pixels are not, a warp map whose reads fail,
// a FIFO named as a picture (display_configs/projector_maps.h, common/image.h).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "common/image.h"
#include "display_configs/projector_maps.h"

using namespace glcast::slave;

namespace {

struct Folder {
    std::string path = "/tmp/glcast-big-inputs-" + std::to_string(getpid());
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() { std::filesystem::remove_all(path); }
};

void chunk(std::string& png, const char* type, const std::string& data) {
    const uint32_t n = uint32_t(data.size());
    const char length[4] = {char(n >> 24), char(n >> 16), char(n >> 8), char(n)};
    png.append(length, 4);
    const std::string body = std::string(type, 4) + data;
    png += body;
    const uint32_t crc = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size())));
    const char sum[4] = {char(crc >> 24), char(crc >> 16), char(crc >> 8), char(crc)};
    png.append(sum, 4);
}

// A valid 8-bit grey PNG of side x side black pixels: some hundred KB for 16384 x 16384.
std::string black_png(uint32_t side) {
    std::string png = "\x89PNG\r\n\x1a\n";
    std::string header(13, '\0');
    for (int i = 0; i < 4; i++) header[i] = header[4 + i] = char(side >> (24 - 8 * i));
    header[8] = 8;  // bit depth; colour type 0 (grey), no interlace
    chunk(png, "IHDR", header);
    z_stream z{};
    deflateInit(&z, 9);
    const std::string row(side + 1, '\0');  // filter byte 0, then the row
    std::string compressed;
    std::vector<unsigned char> out(1 << 16);
    for (uint32_t y = 0; y <= side; y++) {
        const bool last = y == side;
        z.next_in = last ? nullptr : reinterpret_cast<Bytef*>(const_cast<char*>(row.data()));
        z.avail_in = last ? 0 : uInt(row.size());
        do {
            z.next_out = out.data();
            z.avail_out = uInt(out.size());
            deflate(&z, last ? Z_FINISH : Z_NO_FLUSH);
            compressed.append(reinterpret_cast<char*>(out.data()), out.size() - z.avail_out);
        } while (z.avail_out == 0);
    }
    deflateEnd(&z);
    chunk(png, "IDAT", compressed);
    chunk(png, "IEND", "");
    return png;
}

// Runs `work` in a child whose address space is what this process maps now plus `spare`, for at
// most `seconds`: its exit status (0: it answered), or 128 + the signal that ended it.
int in_a_child(size_t spare, unsigned seconds, const std::function<bool()>& work) {
    const pid_t child = fork();
    if (child == 0) {
        size_t pages = 0;
        std::ifstream("/proc/self/statm") >> pages;
        const size_t most = pages * size_t(sysconf(_SC_PAGESIZE)) + spare;
        rlimit limit{most, most};
        setrlimit(RLIMIT_AS, &limit);
        alarm(seconds);
        try {
            _exit(work() ? 0 : 1);
        } catch (...) {
            _exit(2);
        }
    }
    int status = 0;
    waitpid(child, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace

// 16384 x 16384 is within a map's side; as a blend it was decoded whole (1 GiB of RGBA) and then
// made 3 floats a pixel (3 GiB more): the slave ended in an uncaught std::bad_alloc. Its cost is
// known from its header: refused there, naming the file and the limit.
TEST(BigInputs, ABlendMapIsRefusedByWhatItWouldCostBeforeItIsRead) {
    Folder dir;
    const std::string path = dir.path + "/huge_blend.png";
    const std::string png = black_png(16384);
    EXPECT_LT(png.size(), 1u << 20);
    std::ofstream(path, std::ios::binary) << png;
    std::string error;
    const int status = in_a_child(size_t(1536) << 20, 60, [&] {
        ProjectorMaps maps;
        return !load_plain_maps("", path, maps, error) && error.find(path) != std::string::npos &&
               error.find("pixels") != std::string::npos;
    });
    EXPECT_EQ(status, 0) << (status == 2 ? "an exception escaped" : status > 128 ? "the reader was killed" : "accepted");
    ProjectorMaps maps;
    EXPECT_FALSE(load_plain_maps("", path, maps, error));
    EXPECT_NE(error.find("16384x16384"), std::string::npos) << error;
    // One within the bound is read.
    const std::string small = dir.path + "/blend.png";
    std::ofstream(small, std::ios::binary) << black_png(64);
    EXPECT_TRUE(load_plain_maps("", small, maps, error)) << error;
}

// A warp map whose reads fail (a link to a file that errors on read: /proc/self/mem at offset
// 0) ended the slave in an uncaught std::ios_base::failure; a FIFO named as a picture blocked its
// reader forever (calibrate --simulate's outputs and --reference).
TEST(BigInputs, ReadErrorsAndSpecialFilesAreMessages) {
    Folder dir;
    const std::string link = dir.path + "/warp.pfm";
    ASSERT_EQ(symlink("/proc/self/mem", link.c_str()), 0);
    std::string error;
    try {
        ProjectorMaps maps;
        EXPECT_FALSE(load_plain_maps(link, "", maps, error));
        EXPECT_NE(error.find(link), std::string::npos) << error;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "an exception escaped: " << e.what();
    }
    const std::string fifo = dir.path + "/projector.png";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const int status = in_a_child(size_t(256) << 20, 3, [&] {
        Image image;
        return !read_png(fifo, image, error) && error.find("not a regular file") != std::string::npos;
    });
    EXPECT_EQ(status, 0) << (status == 128 + SIGALRM ? "read_png blocked on a FIFO" : "accepted or escaped");
    ProjectorMaps maps;
    EXPECT_FALSE(load_plain_maps("", fifo, maps, error));
    EXPECT_NE(error.find("FIFO"), std::string::npos) << error;
}
