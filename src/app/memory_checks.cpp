#include "memory_checks.hpp"

#include <sys/stat.h>
#include <sys/statvfs.h>

#include <algorithm>

#include "memory_estimate.hpp"
#include "raplas/frontend/memory_estimate.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/memory_budget.hpp"

namespace raplas {

namespace {

// The trace's shape known before the front end runs: no shadow groups.
TraceShape model_shape_up_front(const Scene& s) {
    TraceShape t;
    t.triangles = s.mesh.triangle_count();
    t.spheres = (t.triangles + std::uint64_t(s.tris_per_sphere) - 1) / std::uint64_t(s.tris_per_sphere);
    t.group_size = std::uint32_t(s.group_size);
    t.shadow_group_size = std::uint32_t(s.shadow_group_size);
    const int n = s.group_size;
    t.primary_groups = std::uint64_t((s.width + n - 1) / n) * std::uint64_t((s.height + n - 1) / n);
    return t;
}

// The waveform's least size against the free space of the disk `path` is on.
void check_waveform_size(const std::string& path, const model::SimConfig& c, std::uint64_t primary_groups,
                         std::uint64_t spheres, std::uint64_t triangles) {
    const std::uint64_t passes = (primary_groups + c.iccs - 1) / c.iccs;
    const double cycles = double(passes) * double(std::max(spheres, triangles));
    const double least = 14.0 * cycles;
    const std::size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
    struct statvfs fs{};
    if (::statvfs(dir.c_str(), &fs) != 0) return;  // (a directory that is not there: the writer says so)
    const double free = double(fs.f_bavail) * double(fs.f_frsize);
    if (least <= free) return;
    char n[32];
    std::snprintf(n, sizeof n, "%.3g", cycles);
    throw InputError("--vcd " + path + ": the waveform needs at least " + format_bytes(least) + " (" + n +
                     " cycles in the primary passes alone, at least 14 bytes each for the clock) but its disk has " +
                     format_bytes(free) + " free; simulate a smaller image or more ICCs");
}

const char* command_name(FrontEndUse use) {
    switch (use) {
        case FrontEndUse::render: return "render";
        case FrontEndUse::trace_file:
        case FrontEndUse::trace_streamed: return "trace";
        case FrontEndUse::simulate:
        case FrontEndUse::simulate_streamed: break;
    }
    return "simulate";
}

}  // namespace

void check_front_end(FrontEndUse use, const Scene& s, FrameOptions& fo, const model::SimConfig* model,
                     std::uint32_t window_passes) {
    const char* command = command_name(use);
    const Scene* scene = &s;
    const bool pairless = fo.pairless;
    if (use == FrontEndUse::simulate_streamed || use == FrontEndUse::trace_streamed) {
        // The frame without its groups, the model (its shape without shadow
        // groups, as check_model_up_front) and the window, up front; the
        // shadow phase's arrays and a window of shadow groups before them
        // (the model is resident by then).
        // (A window never holds more groups than the frame has: the primary
        // groups and at most one shadow group a pixel.)
        // (trace_streamed: no model, a window of `window_passes` groups)
        const bool with_model = model != nullptr;
        const model::SimConfig c = with_model ? *model : model::SimConfig{};
        const std::uint64_t window = std::uint64_t(window_passes) * (with_model ? c.iccs : 1);
        const TraceShape up_front = model_shape_up_front(s);
        const std::uint64_t npix = std::uint64_t(s.width) * std::uint64_t(s.height);
        std::vector<MemoryItem> items = frame_memory_up_front(s, fo);
        if (with_model)
            for (auto& m : model::model_memory(c, up_front)) items.push_back(m);
        items.push_back(stream_window_memory(std::min(window, up_front.primary_groups + npix),
                                             std::uint32_t(std::max(s.group_size, s.shadow_group_size)), 0, 0));
        check_memory(command, items);
        GroupStream* stream = fo.stream;
        const std::uint64_t primary = up_front.primary_groups;
        fo.before_shadow = [command, scene, pairless, stream, window, primary, c, up_front, with_model](
                               const Frame& f, std::size_t lit, const ShadowSample& sample) {
            FrameOptions o;
            o.record = true;
            o.pairless = pairless;
            o.stream = stream;
            std::vector<MemoryItem> items = frame_memory_shadow(*scene, o, lit, sample);
            items.push_back(stream_window_memory(std::min<std::uint64_t>(window, primary + lit),
                                                 std::uint32_t(scene->shadow_group_size), sample.sphere_hits,
                                                 pairless ? sample.pairless_runs : 0));
            // What the model's group state and event lists grow by with the
            // groups' sphere hits (its fixed part is resident by now).
            auto sum = [](const std::vector<MemoryItem>& v) {
                double b = 0;
                for (const auto& m : v) b += m.bytes;
                return b;
            };
            if (with_model) {
                const double grown = sum(model::model_memory(c, trace_shape(*scene, f, lit, sample))) -
                                     sum(model::model_memory(c, up_front));
                items.push_back({"the model's group state for the sphere hits", std::max(0.0, grown)});
            } else {
                items.push_back({"the trace block being written", 2.0 * double(kTraceBlockTargetBytes)});
            }
            check_memory(command, items);
        };
        return;
    }
    check_memory(command, frame_memory_up_front(s, fo));
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
    check_memory("simulate", model::model_memory(c, model_shape_up_front(s)));
}

void check_trace_read(const std::string& path, std::uint64_t bytes) {
    // The trace parsed from the file block by block (one block buffered at
    // a time), whose counts the file's blocks give. (Not a trace: the file's
    // size; the reader then says what is wrong.)
    const TraceShape shape = trace_file_shape(path);
    MemoryItem parsed = shape.groups() ? trace_memory(shape) : MemoryItem{"trace file " + path, double(bytes)};
    parsed.bytes += double(kTraceBlockTargetBytes) * 2;  // the block being read
    check_memory("simulate", {parsed});
}

void check_trace_streamed(const model::SimConfig& c, const std::string& path, const Trace& header,
                          std::uint32_t window_passes) {
    // A regular file's blocks give its counts (a pipe is read once, by the
    // reader: its header's shape then).
    struct stat st{};
    const bool regular = ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
    TraceShape shape = regular ? trace_file_shape(path) : TraceShape{};
    if (!shape.groups()) {
        shape = TraceShape{};
        shape.spheres = header.spheres.size();
        shape.triangles = header.triangles.size();
        shape.primary_groups = header.primary_groups;
        shape.group_size = header.group_size;
        shape.shadow_group_size = header.shadow_group_size;
    }
    TraceShape head = shape;  // the header alone
    head.primary_groups = head.shadow_groups = 0;
    head.primary_sphere_hits = head.shadow_sphere_hits = head.pairless_runs = head.pairless_spheres = 0;
    std::vector<MemoryItem> items = model::model_memory(c, shape);
    MemoryItem h = trace_memory(head);
    h.what = "trace header (Sphere and Triangle Memory)";
    h.bytes += 2.0 * double(kTraceBlockTargetBytes);  // the block being read
    items.push_back(h);
    const double groups = double(std::max<std::uint64_t>(1, shape.groups()));
    items.push_back(stream_window_memory(std::min<std::uint64_t>(std::uint64_t(window_passes) * c.iccs, std::max<std::uint64_t>(1, shape.groups())),
                                         std::max(shape.group_size, shape.shadow_group_size),
                                         (shape.primary_sphere_hits + shape.shadow_sphere_hits) / groups,
                                         shape.pairless_runs / groups));
    check_memory("simulate", items);
}

void check_model(const model::SimConfig& c, const Trace& t) { check_memory("simulate", model::model_memory(c, trace_shape(t))); }

void check_waveform_up_front(const std::string& path, const model::SimConfig& c, const Scene& s) {
    const TraceShape t = model_shape_up_front(s);
    check_waveform_size(path, c, t.primary_groups, t.spheres, t.triangles);
}

void check_waveform(const std::string& path, const model::SimConfig& c, const Trace& header) {
    check_waveform_size(path, c, header.primary_groups, header.spheres.size(), header.triangles.size());
}

}  // namespace raplas
