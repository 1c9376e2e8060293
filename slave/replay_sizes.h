// The slave's answers to the length expressions of codegen/annotations/commands.yaml (`sz.`):
// its own driver, whose pixel-store state, bindings and textures the stream has made the
// master's. The generated replay evaluates the shim's expressions with them before each call,
// so what the driver will read is checked against what the stream shipped (docs/security.md).
#pragma once

#include "glcast_gl_api.h"
#include "protocol/size_queries.h"

namespace glcast::slave {

class ReplaySizeQueries : public SizeQueries {
public:
    explicit ReplaySizeQueries(const GlApi& api) : api_(api) {}

    int64_t driver_count(uint32_t pname) override;
    int64_t tex_level(uint32_t target, int32_t level, uint32_t pname) override;
    bool client_pointer(const void* pointer) override;
    bool enabled(uint32_t cap) override;
    bool read_buffer(uint32_t target, int64_t offset, int64_t bytes, void* out) override;
    // The current context's OpenGL ES version (0: desktop): asked only what it has, as the shim
    // asked the master's.
    void set_es_version(int es) { es_ = es; }

private:
    const GlApi& api_;
    int es_ = 0;
};

// The buffer target whose binding query is `binding` (GL_ARRAY_BUFFER_BINDING ->
// GL_ARRAY_BUFFER); 0 for a query that names no buffer binding.
uint32_t binding_target(uint32_t binding);
uint32_t buffer_binding(uint32_t target);  // the other way round

}  // namespace glcast::slave
