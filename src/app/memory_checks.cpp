#include "memory_checks.hpp"

#include "memory_estimate.hpp"
#include "raplas/frontend/memory_estimate.hpp"

namespace raplas {

namespace {

const char* command_name(FrontEndUse use) {
    switch (use) {
        case FrontEndUse::render: return "render";
        case FrontEndUse::trace_file: return "trace";
        case FrontEndUse::simulate: break;
    }
    return "simulate";
}

}  // namespace

void check_front_end(FrontEndUse use, const Scene& s, FrameOptions& fo) {
    const char* command = command_name(use);
    check_memory(command, frame_memory_up_front(s, fo));
    const Scene* scene = &s;
    const bool pairless = fo.pairless;
    fo.before_shadow = [use, command, scene, pairless](const Frame& f, std::size_t lit, const ShadowSample& sample) {
        FrameOptions o;
        o.record = use != FrontEndUse::render;
        o.pairless = pairless;
        std::vector<MemoryItem> items = frame_memory_shadow(*scene, o, lit, sample);
        if (o.record) {
            const TraceShape shape = trace_shape(*scene, f, lit, sample);
            items.push_back(trace_memory(shape, use == FrontEndUse::simulate));  // simulate moves the frame into it
            if (use == FrontEndUse::trace_file) items.push_back(trace_file_memory(shape));
        }
        check_memory(command, items);
    };
}

void check_model_up_front(const model::SimConfig& c, const Scene& s) {
    TraceShape t;
    t.triangles = s.mesh.triangle_count();
    t.spheres = (t.triangles + std::uint64_t(s.tris_per_sphere) - 1) / std::uint64_t(s.tris_per_sphere);
    t.group_size = std::uint32_t(s.group_size);
    t.shadow_group_size = std::uint32_t(s.shadow_group_size);
    const int n = s.group_size;
    t.primary_groups = std::uint64_t((s.width + n - 1) / n) * std::uint64_t((s.height + n - 1) / n);
    check_memory("simulate", model::model_memory(c, t));
}

void check_trace_read(const std::string& path, std::uint64_t bytes) {
    // The file in one buffer and the trace parsed from it, whose counts the
    // file's first fields give. (Not a trace: at least the file's size; the
    // reader then says what is wrong.)
    const TraceShape shape = trace_file_shape(path);
    MemoryItem parsed = shape.groups() ? trace_memory(shape) : MemoryItem{"trace parsed from it", double(bytes)};
    check_memory("simulate", {{"trace file " + path, double(bytes)}, parsed});
}

void check_model(const model::SimConfig& c, const Trace& t) { check_memory("simulate", model::model_memory(c, trace_shape(t))); }

}  // namespace raplas
