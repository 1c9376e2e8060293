// The recording GL's hand-written half: the log, the default answers of an empty driver, and
// the backend that carries it (recording_gl.h).
#include "slave/backends/recording/recording_gl.h"

#include "common/gl_headers.h"
#include "glcast_commands.h"
#include "protocol/command_info.h"

namespace glcast::slave {
namespace {

thread_local RecordingGl* g_current = nullptr;  // as a driver keeps it: per thread

class RecordingBackend final : public Backend {
public:
    explicit RecordingBackend(std::shared_ptr<RecordingGl> gl) : gl_(std::move(gl)), previous_(g_current) {
        g_current = gl_.get();
    }
    ~RecordingBackend() override { g_current = previous_; }
    const char* name() const override { return "recording"; }
    bool create_context(uint32_t, uint32_t, const ContextRequest&, std::string&) override { return true; }
    bool make_current(uint32_t id, int, int, std::string&) override {
        gl_->current_context = id;
        if (id) g_current = gl_.get();  // as a driver does: calls go to the context made current last
        return true;
    }
    void destroy_context(uint32_t id) override {
        if (gl_->current_context == id) gl_->current_context = 0;
    }
    void* proc_address(const char* name) override {
        const int opcode = opcode_by_name(name);
        return opcode < 0 ? nullptr : recording_gl_function(uint32_t(opcode));
    }
    void present() override {}

private:
    std::shared_ptr<RecordingGl> gl_;
    RecordingGl* previous_;
};

}  // namespace

const char* RecordedCall::name() const {
    const CommandInfo* info = command_info(opcode);
    return info ? info->name : "?";
}

std::vector<std::string> RecordingGl::texts(const std::string& prefix) const {
    std::vector<std::string> out;
    for (const RecordedCall& c : calls)
        if (c.text.compare(0, prefix.size(), prefix) == 0) out.push_back(c.text);
    return out;
}

RecordingGl* RecordingGl::current() { return g_current; }

RecordedCall& RecordingGl::begin(uint32_t opcode) {
    calls.emplace_back();
    RecordedCall& c = calls.back();
    c.opcode = opcode;
    c.context = current_context;
    c.text = c.name();
    c.text += '(';
    return c;
}

// What a driver with no objects and no errors answers.
void RecordingGl::finish(RecordedCall& c) {
    if (c.opcode == OP_glCheckFramebufferStatus) c.reply = GL_FRAMEBUFFER_COMPLETE;
    if (answer) answer(c);
}

uint32_t RecordingGl::new_names(uint32_t count) {
    const uint32_t first = next_name_;
    next_name_ += count;
    return first;
}

std::unique_ptr<Backend> make_recording_backend(std::shared_ptr<RecordingGl> gl) {
    return std::make_unique<RecordingBackend>(std::move(gl));
}

}  // namespace glcast::slave
