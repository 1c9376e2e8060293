// Null backend: contexts that exist only by name and a driver whose every entry point does
// nothing and returns 0. A slave on it receives, decodes and maps the stream but rasterizes
// nothing: the benchmark of distribution alone (bench/wall_bench.py), without the cost of
// llvmpipe on a 2-core machine. Outputs the slave reads back stay zero, so replay reports
// errors (buffers it cannot map); frames are not meaningful.
#include "slave/backends/backends_internal.h"

namespace glcast::slave {
namespace {

// Called through pointers of every GL signature: on x86-64 and aarch64 the caller owns the
// arguments and a 0 in the return register serves integer and pointer results alike.
extern "C" long glcast_null_gl_function() { return 0; }

class NullBackend final : public Backend {
public:
    const char* name() const override { return "null"; }
    bool create_context(uint32_t, uint32_t, const ContextRequest&, std::string&) override { return true; }
    bool make_current(uint32_t, int, int, std::string&) override { return true; }
    void destroy_context(uint32_t) override {}
    void* proc_address(const char*) override { return reinterpret_cast<void*>(&glcast_null_gl_function); }
    void present() override {}
};

}  // namespace

std::unique_ptr<Backend> make_null_backend(std::string&) { return std::make_unique<NullBackend>(); }

}  // namespace glcast::slave
