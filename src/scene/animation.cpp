#include "raplas/scene/animation.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>
#include <utility>

#include "raplas/util/error.hpp"
#include "raplas/util/nearest.hpp"

namespace raplas {

namespace {

// The built-in animation `default`: the built-in scene over 48 frames, its
// box turning once about its vertical axis, the camera circling the scene
// once above the objects and inside the walls.
constexpr int kBuiltinFrames = 48;
const Orbit kBuiltinOrbit{{0.0, 0.4, -0.2}, 2.5, 4.6, 1.0, 30.0};
const Vec3d kBuiltinBoxPivot{0.9, 0.0, -0.7};

const char* const kOrbitKeys[] = {"animation.orbit.center", "animation.orbit.radius", "animation.orbit.eye_height",
                                  "animation.orbit.turns", "animation.orbit.start_deg"};

// A real as TOML text that reads back to the same double.
std::string toml_real(double d) {
    char buf[40];
    for (int prec = 1; prec <= 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, d);
        if (std::strtod(buf, nullptr) == d) break;
    }
    std::string t = buf;
    if (t.find_first_of(".eEn") == std::string::npos) t += ".0";
    return t;
}

std::string toml_vec(const Vec3d& v) { return "[" + toml_real(v.x) + ", " + toml_real(v.y) + ", " + toml_real(v.z) + "]"; }

std::string toml_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += c;
        } else if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    return out + "\"";
}

// "" when the camera can be used, else what is wrong with it.
std::string camera_problem(const Camera& c) {
    if (!all_finite(c.eye) || !all_finite(c.look_at) || !all_finite(c.up) || !std::isfinite(c.fov_deg))
        return "is not finite (values too large)";
    const double dist = length(c.eye - c.look_at);
    if (!(dist > 0)) return "eye equals look_at";
    if (!std::isfinite(dist)) return "eye and look_at are too far apart";
    const double side = length(cross(c.eye - c.look_at, c.up));
    if (!std::isfinite(side)) return "up is too long for the view direction";
    if (side <= 1e-12 * dist) return "up is parallel to the view direction (or zero)";
    return "";
}

// The frame of keyframe `k`, which must come after `prev` (the keyframe before it, if any).
int keyframe_frame(const ParamSet& k, const ParamSet* prev) {
    if (!k.is_given("frame")) throw InputError(k.item_origin() + ": " + k.item_path() + " has no frame");
    const auto f = static_cast<int>(k.get_int("frame"));
    if (prev && f <= prev->get_int("frame"))
        throw InputError(k.origin("frame") + ": " + k.item_path() + ".frame = " + std::to_string(f) + " is not after " +
                         prev->item_path() + ".frame = " + std::to_string(prev->get_int("frame")) +
                         ": keyframes must be in increasing frame order");
    return f;
}

// The keyframes around `frame`: a == b on a keyframe's frame and before the
// first or after the last (that keyframe's values as they are), else a < b
// and the fraction t of the way from a to b.
struct Span {
    std::size_t a = 0, b = 0;
    double t = 0;
};

template <class Key>
Span span_at(const std::vector<Key>& keys, int frame) {
    const std::size_t n = keys.size();
    if (frame <= keys.front().frame) return {0, 0, 0.0};
    if (frame >= keys.back().frame) return {n - 1, n - 1, 0.0};
    const auto after = std::upper_bound(keys.begin(), keys.end(), frame, [](int f, const Key& k) { return f < k.frame; });
    const auto b = static_cast<std::size_t>(after - keys.begin()), a = b - 1;
    if (keys[a].frame == frame) return {a, a, 0.0};
    return {a, b, double(frame - keys[a].frame) / double(keys[b].frame - keys[a].frame)};
}

double lerp(double x, double y, double t) { return x + (y - x) * t; }
Vec3d lerp(const Vec3d& x, const Vec3d& y, double t) { return {lerp(x.x, y.x, t), lerp(x.y, y.y, t), lerp(x.z, y.z, t)}; }

// A unit direction from any finite non-zero vector (scaled first: no overflow).
Vec3d unit(const Vec3d& v) {
    const double m = max_abs(v);
    return m > 0 ? normalize(v / m) : v;
}

struct Quat {
    double w = 1, x = 0, y = 0, z = 0;
};

Quat axis_angle(const Vec3d& axis, double deg) {
    const Vec3d u = unit(axis);
    const double half = deg * M_PI / 360.0, s = std::sin(half);
    return {std::cos(half), u.x * s, u.y * s, u.z * s};
}

// Spherical interpolation along the shorter arc.
Quat slerp(const Quat& p, Quat q, double t) {
    double d = p.w * q.w + p.x * q.x + p.y * q.y + p.z * q.z;
    if (d < 0) {
        q = {-q.w, -q.x, -q.y, -q.z};
        d = -d;
    }
    double s0 = 1 - t, s1 = t;
    if (d < 0.9995) {
        const double theta = std::acos(d), st = std::sin(theta);
        s0 = std::sin((1 - t) * theta) / st;
        s1 = std::sin(t * theta) / st;
    }
    Quat r{s0 * p.w + s1 * q.w, s0 * p.x + s1 * q.x, s0 * p.y + s1 * q.y, s0 * p.z + s1 * q.z};
    const double n = std::sqrt(r.w * r.w + r.x * r.x + r.y * r.y + r.z * r.z);
    return {r.w / n, r.x / n, r.y / n, r.z / n};
}

void rotate_by(RigidMotion& m, const Quat& q) {
    m.rotates = true;
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    m.r[0][0] = 1 - 2 * (y * y + z * z), m.r[0][1] = 2 * (x * y - w * z), m.r[0][2] = 2 * (x * z + w * y);
    m.r[1][0] = 2 * (x * y + w * z), m.r[1][1] = 1 - 2 * (x * x + z * z), m.r[1][2] = 2 * (y * z - w * x);
    m.r[2][0] = 2 * (x * z - w * y), m.r[2][1] = 2 * (y * z + w * x), m.r[2][2] = 1 - 2 * (x * x + y * y);
}

// The triangles of the mesh as loaded: those before the added ones (the floor).
std::size_t own_triangles(const Mesh& m) {
    if (m.triangle_object.size() != m.triangles.size()) return m.triangles.size();
    const auto added = std::find(m.triangle_object.begin(), m.triangle_object.end(), Mesh::kAddedObject);
    return static_cast<std::size_t>(added - m.triangle_object.begin());
}

std::string count_mismatch(const std::string& file, int frame, std::size_t count, const std::string& first,
                           std::size_t first_count) {
    return file + ": frame " + std::to_string(frame) + " has " + std::to_string(count) + " triangles, frame 0 (" + first +
           ") has " + std::to_string(first_count) + ": every file of animation.mesh_sequence must have as many";
}

// Frame `frame`'s mesh of a sequence: its file, the object numbers of frame
// 0's and the geometry added to the still mesh (the floor) as it is there.
Mesh sequence_mesh(const Mesh& still, const Animation& a, int frame) {
    if (frame == 0) return still;
    const std::string& file = a.sequence_files[static_cast<std::size_t>(frame)];
    Mesh m = load_obj(file);
    const std::size_t own = own_triangles(still);
    if (m.triangles.size() != own)
        throw InputError(count_mismatch(file, frame, m.triangles.size(), a.sequence_files[0], own));
    if (still.triangle_object.size() == still.triangles.size()) {
        m.triangle_object.assign(still.triangle_object.begin(), still.triangle_object.begin() + long(own));
        m.object_names = still.object_names;
    } else {
        m.triangle_object.clear();
        m.object_names.clear();
    }
    std::map<std::uint32_t, std::uint32_t> vertex;
    std::map<std::int32_t, std::int32_t> material;
    for (std::size_t t = own; t < still.triangles.size(); ++t) {
        std::array<std::uint32_t, 3> tri{};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = still.triangles[t][k];
            const auto it = vertex.emplace(v, static_cast<std::uint32_t>(m.vertices.size()));
            if (it.second) m.vertices.push_back(still.vertices[v]);
            tri[k] = it.first->second;
        }
        m.triangles.push_back(tri);
        const std::int32_t mt = still.triangle_material[t];
        const auto it = material.emplace(mt, static_cast<std::int32_t>(m.materials.size()));
        if (it.second) m.materials.push_back(still.materials[static_cast<std::size_t>(mt)]);
        m.triangle_material.push_back(it.first->second);
        if (!m.triangle_object.empty()) m.triangle_object.push_back(Mesh::kAddedObject);
    }
    return m;
}

// Moves the objects of the tracks. A vertex that triangles of objects with
// different motions share is copied, one copy per motion.
void move_objects(Mesh& m, const Animation& a, int frame) {
    const bool named = m.triangle_object.size() == m.triangles.size();
    std::vector<int> track_of(m.object_names.size(), -1);
    int whole = -1;
    std::vector<RigidMotion> rigid;
    for (std::size_t i = 0; i < a.objects.size(); ++i) {
        const ObjectTrack& tr = a.objects[i];
        if (tr.object < 0) whole = static_cast<int>(i);
        else if (static_cast<std::size_t>(tr.object) < track_of.size()) track_of[static_cast<std::size_t>(tr.object)] = static_cast<int>(i);
        rigid.push_back(motion_at(tr, frame));
    }
    // The motion of a triangle: kStill (added geometry), -1 (the whole mesh's only) or a track.
    constexpr int kStill = -2, kUnseen = INT_MIN;
    auto motion = [&](std::size_t t) {
        if (!named) return -1;
        const std::int32_t obj = m.triangle_object[t];
        if (obj == Mesh::kAddedObject) return kStill;
        return obj >= 0 && static_cast<std::size_t>(obj) < track_of.size() ? track_of[static_cast<std::size_t>(obj)] : -1;
    };
    std::vector<int> vmotion(m.vertices.size(), kUnseen);
    std::map<std::pair<std::uint32_t, int>, std::uint32_t> copies;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const int k = motion(t);
        for (auto& v : m.triangles[t]) {
            if (vmotion[v] == kUnseen) vmotion[v] = k;
            if (vmotion[v] == k) continue;
            const auto it = copies.emplace(std::make_pair(v, k), static_cast<std::uint32_t>(m.vertices.size()));
            if (it.second) {
                const Vec3f p = m.vertices[v];
                m.vertices.push_back(p);
                vmotion.push_back(k);
            }
            v = it.first->second;
        }
    }
    for (std::size_t i = 0; i < m.vertices.size(); ++i) {
        const int k = vmotion[i];
        if (k == kUnseen || k == kStill || (k < 0 && whole < 0)) continue;
        Vec3d p = to_d(m.vertices[i]);
        if (k >= 0) p = rigid[static_cast<std::size_t>(k)].apply(p);
        if (whole >= 0) p = rigid[static_cast<std::size_t>(whole)].apply(p);
        const Vec3f f = to_f(p);
        if (!all_finite(f))
            throw InputError("animation: frame " + std::to_string(frame) + ": animation.object '" +
                             a.objects[static_cast<std::size_t>(k >= 0 ? k : whole)].name +
                             "' moves a vertex out of the float range");
        m.vertices[i] = f;
    }
}

ObjectTrack builtin_box_track(const Mesh& m, int frames) {
    ObjectTrack t;
    t.name = "box";
    t.pivot = kBuiltinBoxPivot;
    t.object = static_cast<std::int32_t>(std::find(m.object_names.begin(), m.object_names.end(), "box") - m.object_names.begin());
    ObjectKey first, last;
    last.frame = frames;
    last.angle_deg = 360;
    t.keys = {first, last};
    return t;
}

// The object a track names in the still mesh (-1 for "*").
std::int32_t object_named(const ParamSet& k, const std::string& name, const Mesh& m) {
    if (name == "*") return -1;
    const std::string at = k.origin("name") + ": " + k.item_path() + ".name = '" + name + "': ";
    if (name.empty()) throw InputError(at + "give an OBJ object or group name, or \"*\" for the whole mesh");
    if (m.triangle_object.size() == m.triangles.size()) {
        const auto it = std::find(m.object_names.begin(), m.object_names.end(), name);
        if (it != m.object_names.end()) return static_cast<std::int32_t>(it - m.object_names.begin());
    }
    std::vector<std::string> names;
    for (const auto& n : m.object_names)
        if (!n.empty()) names.push_back(n);
    std::string msg = at + m.source + " has no object or group of that name";
    const std::vector<std::string> near = nearest_names(name, names);
    if (!near.empty()) throw InputError(msg + did_you_mean(near));
    if (names.empty()) throw InputError(msg + " (it has none; \"*\" is the whole mesh)");
    std::string list;
    for (std::size_t i = 0; i < names.size() && i < 8; ++i) list += (i ? ", " : "") + names[i];
    if (names.size() > 8) list += ", ...";
    throw InputError(msg + " (it has " + list + "; \"*\" is the whole mesh)");
}

// The file of `frame` of the sequence, found as `mesh` is.
std::string sequence_file(const ParamSet& p, int frame) {
    const std::string pattern = p.get_string("animation.mesh_sequence");
    const std::string key = p.origin("animation.mesh_sequence") + ": ";
    std::string name;
    try {
        name = sequence_file_name(pattern, p.get_int("animation.sequence_first") + frame);
    } catch (const std::invalid_argument& e) {
        throw InputError(key + "scene key 'animation.mesh_sequence' = '" + pattern + "' " + e.what());
    }
    try {
        return resolve_mesh_path(name, p.file_dir());
    } catch (const InputError& e) {
        throw InputError(key + "animation.mesh_sequence, frame " + std::to_string(frame) + ": " + e.what());
    }
}

}  // namespace

void add_animation_params(ParamSet& p) {
    p.add_int("animation.frames", 1, 1, kMaxFrames, "number of frames, numbered 0 .. frames - 1");
    p.add_real("animation.fps", 24.0, 0.001, 1000.0, "frames per second");
    p.add_string("animation.builtin", std::string("none"),
                 "built-in animation, with no mesh: default (the built-in scene, its box turning, the camera circling "
                 "it), wave (a waving grid), or none",
                 {"none", "default", "wave"});
    p.add_string("animation.mesh_sequence", std::string(""),
                 "deforming mesh: one OBJ per frame, named by this pattern with sequence_first + frame in place of "
                 "its %d or %0Nd (\"\" = none); replaces mesh");
    p.add_int("animation.sequence_first", 0, 0, 1000000000, "the number in the file name of frame 0 of mesh_sequence");
    p.add_vec3("animation.orbit.center", std::nullopt,
               "orbit: the point the camera circles and looks at (default: the still camera's look_at); any orbit "
               "key makes the camera orbit");
    p.unset_means("animation.orbit.center", "unset");
    p.add_optional_real("animation.orbit.radius", 1e-9, 1e12,
                        "orbit: horizontal distance of the eye from center (default: the still camera's)");
    p.add_optional_real("animation.orbit.eye_height", -1e12, 1e12,
                        "orbit: height of the eye above center (default: the still camera's)");
    p.add_optional_real("animation.orbit.turns", -1000.0, 1000.0,
                        "orbit: turns over the animation, counter-clockwise seen from above (default 1)");
    p.add_optional_real("animation.orbit.start_deg", -360000.0, 360000.0,
                        "orbit: angle of the eye at frame 0, degrees from +z toward +x (default: the still camera's)");

    ParamSet cam("scene");
    cam.add_int("frame", 0, 0, kMaxFrames, "frame number (required)");
    cam.add_vec3("eye", std::nullopt, "camera position (default: the still camera's)");
    cam.add_vec3("look_at", std::nullopt, "point looked at (default: the still camera's)");
    cam.add_vec3("up", std::nullopt, "up direction (default: the still camera's)");
    cam.add_optional_real("fov_deg", 1.0, 170.0, "vertical field of view, degrees (default: the still camera's)");
    p.add_tables("animation.camera", cam,
                 "camera keyframes in increasing frame order, linearly interpolated, held before the first and after "
                 "the last");

    ParamSet light("scene");
    light.add_int("frame", 0, 0, kMaxFrames, "frame number (required)");
    light.add_vec3("corner", std::nullopt, "light.corner at that frame (required)");
    p.add_tables("animation.light", light, "keyframes of the light's corner, as the camera's");

    ParamSet key("scene");
    key.add_int("frame", 0, 0, kMaxFrames, "frame number (required)");
    key.add_vec3("translate", Vec3d(0, 0, 0), "translation");
    key.add_vec3("axis", Vec3d(0, 1, 0), "rotation axis");
    key.add_real("angle_deg", 0.0, -360000.0, 360000.0, "rotation about axis through pivot, degrees");
    key.add_real("scale", 1.0, 1e-6, 1e6, "uniform scale about pivot");
    ParamSet object("scene");
    object.add_string("name", std::nullopt, "OBJ object or group name, or \"*\" for the whole mesh (required)");
    object.add_vec3("pivot", Vec3d(0, 0, 0), "centre of rotation and scale");
    object.add_tables("keys", key, "keyframes in increasing frame order, as the camera's");
    p.add_tables("animation.object", object,
                 "rigid motions: a point p goes to pivot + translate + R(axis, angle_deg) (scale (p - pivot))");
}

std::string sequence_file_name(const std::string& pattern, long long n) {
    std::string out;
    int fields = 0;
    for (std::size_t i = 0; i < pattern.size(); ++i) {
        if (pattern[i] != '%') {
            out += pattern[i];
            continue;
        }
        if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
            out += '%';
            ++i;
            continue;
        }
        std::size_t j = i + 1, width = 0;
        if (j + 1 < pattern.size() && pattern[j] == '0' && pattern[j + 1] >= '1' && pattern[j + 1] <= '9') {
            width = static_cast<std::size_t>(pattern[j + 1] - '0');
            j += 2;
        }
        if (j >= pattern.size() || pattern[j] != 'd')
            throw std::invalid_argument("has '" + pattern.substr(i, std::min(j + 1, pattern.size()) - i) +
                                        "': a '%' takes d or 0Nd (N one digit: zero-padded to N), or another '%'");
        if (++fields > 1) throw std::invalid_argument("has more than one %d");
        std::string num = std::to_string(n);
        if (num.size() < width) num.insert(0, width - num.size(), '0');
        out += num;
        i = j;
    }
    if (fields == 0) throw std::invalid_argument("has no %d (or %0Nd) for the frame number");
    return out;
}

std::vector<std::string> animation_mesh_files(const ParamSet& p) {
    std::vector<std::string> files;
    if (p.get_string("animation.mesh_sequence").empty()) return files;
    const bool builtin = p.get_string("animation.builtin") != "none";
    const int frames = builtin && !p.is_given("animation.frames") ? kBuiltinFrames
                                                                   : static_cast<int>(p.get_int("animation.frames"));
    for (int f = 0; f < frames; ++f) files.push_back(sequence_file(p, f));
    return files;
}

std::optional<Mesh> animation_still_mesh(const ParamSet& p, const std::string& mesh_override) {
    const std::string builtin = p.get_string("animation.builtin");
    const std::string sequence = p.get_string("animation.mesh_sequence");
    if (sequence.empty() && builtin == "none") return std::nullopt;
    const std::string what = !sequence.empty() ? "animation.mesh_sequence" : "animation.builtin";
    if (!sequence.empty() && builtin != "none")
        throw InputError(p.origin("animation.builtin") + ": animation.builtin and animation.mesh_sequence each give "
                         "the mesh: give one");
    if (!mesh_override.empty()) throw InputError("--mesh: " + what + " gives the mesh: give one");
    if (!p.get_string("mesh").empty())
        throw InputError(p.origin("mesh") + ": mesh and " + what + " each give the mesh: give one");
    if (!sequence.empty()) return load_obj(sequence_file(p, 0));
    if (builtin == "wave") return wave_mesh(static_cast<int>(p.get_int("builtin_detail")), 0.0);
    return std::nullopt;  // default: the built-in scene
}

Animation animation_from_params(const ParamSet& p, const Scene& still) {
    Animation a;
    const std::string builtin = p.get_string("animation.builtin");
    a.fps = p.get_real("animation.fps");
    a.frames = builtin != "none" && !p.is_given("animation.frames") ? kBuiltinFrames
                                                                    : static_cast<int>(p.get_int("animation.frames"));

    const auto& cams = p.get_tables("animation.camera");
    for (std::size_t i = 0; i < cams.size(); ++i) {
        const ParamSet& k = cams[i];
        CameraKey key;
        key.frame = keyframe_frame(k, i ? &cams[i - 1] : nullptr);
        key.camera = still.camera;
        if (auto v = k.get_vec3("eye")) key.camera.eye = *v;
        if (auto v = k.get_vec3("look_at")) key.camera.look_at = *v;
        if (auto v = k.get_vec3("up")) key.camera.up = *v;
        if (auto f = k.get_optional_real("fov_deg")) key.camera.fov_deg = *f;
        const std::string problem = camera_problem(key.camera);
        if (!problem.empty()) throw InputError(k.item_origin() + ": " + k.item_path() + ": the camera's " + problem);
        a.camera.push_back(key);
    }

    const char* orbit_key = nullptr;
    for (const char* k : kOrbitKeys)
        if (!orbit_key && (std::string(k) == kOrbitKeys[0] ? p.get_vec3(k).has_value() : p.get_optional_real(k).has_value()))
            orbit_key = k;
    if (orbit_key && !a.camera.empty())
        throw InputError(p.origin(orbit_key) + ": give animation.camera keyframes or animation.orbit, not both");
    if (orbit_key) {
        Orbit o;
        o.center = p.get_vec3("animation.orbit.center").value_or(still.camera.look_at);
        const Vec3d d = still.camera.eye - o.center;
        o.radius = p.get_optional_real("animation.orbit.radius").value_or(std::hypot(d.x, d.z));
        o.eye_height = p.get_optional_real("animation.orbit.eye_height").value_or(d.y);
        o.turns = p.get_optional_real("animation.orbit.turns").value_or(1.0);
        o.start_deg = p.get_optional_real("animation.orbit.start_deg").value_or(std::atan2(d.x, d.z) * 180.0 / M_PI);
        if (!(o.radius > 0) || !std::isfinite(o.radius))
            throw InputError(p.origin(orbit_key) + ": animation.orbit: the still camera is straight above or below "
                             "the orbit's center; give animation.orbit.radius");
        a.orbit = o;
    } else if (builtin == "default" && a.camera.empty()) {
        a.orbit = kBuiltinOrbit;
    }

    const auto& lights = p.get_tables("animation.light");
    for (std::size_t i = 0; i < lights.size(); ++i) {
        const ParamSet& k = lights[i];
        LightKey key;
        key.frame = keyframe_frame(k, i ? &lights[i - 1] : nullptr);
        const auto corner = k.get_vec3("corner");
        if (!corner) throw InputError(k.item_origin() + ": " + k.item_path() + " has no corner");
        key.corner = *corner;
        a.light.push_back(key);
    }

    const auto& objects = p.get_tables("animation.object");
    for (std::size_t i = 0; i < objects.size(); ++i) {
        const ParamSet& o = objects[i];
        ObjectTrack track;
        if (!o.is_given("name")) throw InputError(o.item_origin() + ": " + o.item_path() + " has no name");
        track.name = o.get_string("name");
        track.object = object_named(o, track.name, still.mesh);
        for (std::size_t j = 0; j < i; ++j)
            if (a.objects[j].name == track.name)
                throw InputError(o.origin("name") + ": " + o.item_path() + ".name = '" + track.name + "' is moved by " +
                                 objects[j].item_path() + " already");
        track.pivot = *o.get_vec3("pivot");
        const auto& keys = o.get_tables("keys");
        if (keys.empty()) throw InputError(o.item_origin() + ": " + o.item_path() + " has no keys ([[" + o.item_path().substr(0, o.item_path().rfind('[')) + ".keys]])");
        for (std::size_t j = 0; j < keys.size(); ++j) {
            const ParamSet& k = keys[j];
            ObjectKey key;
            key.frame = keyframe_frame(k, j ? &keys[j - 1] : nullptr);
            key.translate = *k.get_vec3("translate");
            key.axis = *k.get_vec3("axis");
            key.angle_deg = k.get_real("angle_deg");
            key.scale = k.get_real("scale");
            if (max_abs(key.axis) == 0)
                throw InputError(k.origin("axis") + ": " + k.item_path() + ".axis is zero: give a direction");
            track.keys.push_back(key);
        }
        a.objects.push_back(track);
    }
    if (objects.empty() && builtin == "default") a.objects.push_back(builtin_box_track(still.mesh, a.frames));

    if (!p.get_string("animation.mesh_sequence").empty()) {
        a.deform = Deform::sequence;
        const std::size_t own = own_triangles(still.mesh);
        for (int f = 0; f < a.frames; ++f) a.sequence_files.push_back(sequence_file(p, f));
        for (int f = 1; f < a.frames; ++f) {
            const std::string& file = a.sequence_files[static_cast<std::size_t>(f)];
            const Mesh m = load_obj(file);
            if (m.triangles.size() != own) throw InputError(count_mismatch(file, f, m.triangles.size(), a.sequence_files[0], own));
        }
    } else if (builtin == "wave") {
        a.deform = Deform::wave;
        a.wave_detail = static_cast<int>(p.get_int("builtin_detail"));
    }
    return a;
}

void resolve_animation_params(ParamSet& p, const Animation& a) {
    p.set("animation.frames=" + std::to_string(a.frames));
    if (a.orbit) {
        p.set("animation.orbit.center=" + toml_vec(a.orbit->center));
        p.set("animation.orbit.radius=" + toml_real(a.orbit->radius));
        p.set("animation.orbit.eye_height=" + toml_real(a.orbit->eye_height));
        p.set("animation.orbit.turns=" + toml_real(a.orbit->turns));
        p.set("animation.orbit.start_deg=" + toml_real(a.orbit->start_deg));
    }
    if (p.get_tables("animation.object").empty() && !a.objects.empty()) {
        std::string tracks;
        for (const ObjectTrack& t : a.objects) {
            std::string keys;
            for (const ObjectKey& k : t.keys)
                keys += std::string(keys.empty() ? "" : ", ") + "{frame = " + std::to_string(k.frame) +
                        ", translate = " + toml_vec(k.translate) + ", axis = " + toml_vec(k.axis) +
                        ", angle_deg = " + toml_real(k.angle_deg) + ", scale = " + toml_real(k.scale) + "}";
            tracks += std::string(tracks.empty() ? "" : ", ") + "{name = " + toml_string(t.name) +
                      ", pivot = " + toml_vec(t.pivot) + ", keys = [" + keys + "]}";
        }
        p.set("animation.object=[" + tracks + "]");
    }
}

RigidMotion motion_at(const ObjectTrack& track, int frame) {
    const Span s = span_at(track.keys, frame);
    const ObjectKey& a = track.keys[s.a];
    const ObjectKey& b = track.keys[s.b];
    RigidMotion r;
    r.pivot = track.pivot;
    if (s.a == s.b) {
        r.translate = a.translate;
        r.scale = a.scale;
        if (a.angle_deg != 0) rotate_by(r, axis_angle(a.axis, a.angle_deg));
        return r;
    }
    r.translate = lerp(a.translate, b.translate, s.t);
    r.scale = lerp(a.scale, b.scale, s.t);
    if (a.axis == b.axis) {
        // One axis: the angle itself is interpolated, so a pair can turn by more than half a turn.
        const double angle = lerp(a.angle_deg, b.angle_deg, s.t);
        if (angle != 0) rotate_by(r, axis_angle(a.axis, angle));
    } else if (a.angle_deg != 0 || b.angle_deg != 0) {
        rotate_by(r, slerp(axis_angle(a.axis, a.angle_deg), axis_angle(b.axis, b.angle_deg), s.t));
    }
    return r;
}

bool animation_keys_given(const ParamSet& p) {
    for (const auto& k : p.keys())
        if (k.rfind("animation.", 0) == 0 && p.is_given(k)) return true;
    return false;
}

int frame_count(const Scene& s) { return s.animation ? s.animation->frames : 1; }

Camera camera_at_frame(const Animation& a, const Camera& still, int frame) {
    if (!a.camera.empty()) {
        const Span s = span_at(a.camera, frame);
        if (s.a == s.b) return a.camera[s.a].camera;
        const Camera& x = a.camera[s.a].camera;
        const Camera& y = a.camera[s.b].camera;
        Camera c;
        c.eye = lerp(x.eye, y.eye, s.t);
        c.look_at = lerp(x.look_at, y.look_at, s.t);
        c.up = lerp(x.up, y.up, s.t);
        c.fov_deg = lerp(x.fov_deg, y.fov_deg, s.t);
        return c;
    }
    if (a.orbit) {
        const Orbit& o = *a.orbit;
        const double deg = o.start_deg + 360.0 * o.turns * double(frame) / double(a.frames);
        const double rad = deg * M_PI / 180.0;
        Camera c = still;
        c.look_at = o.center;
        c.eye = o.center + Vec3d(o.radius * std::sin(rad), o.eye_height, o.radius * std::cos(rad));
        return c;
    }
    return still;
}

Scene scene_at_frame(const Scene& base, const Animation& a, int frame) {
    if (frame < 0 || frame >= a.frames)
        throw InputError("frame " + std::to_string(frame) + " is not in the animation (frames 0 to " +
                         std::to_string(a.frames - 1) + ")");
    const std::string at = "animation: frame " + std::to_string(frame) + ": ";
    Scene s = base;
    s.animation = nullptr;
    if (!a.camera.empty() || a.orbit) {
        s.camera = camera_at_frame(a, base.camera, frame);
        s.camera_auto = false;
        const std::string problem = camera_problem(s.camera);
        if (!problem.empty()) throw InputError(at + "the camera's " + problem);
    }
    if (!a.light.empty()) {
        const Span sp = span_at(a.light, frame);
        s.light.corner = sp.a == sp.b ? a.light[sp.a].corner : lerp(a.light[sp.a].corner, a.light[sp.b].corner, sp.t);
        s.light_auto = false;
        if (!all_finite(s.light.corner + s.light.edge_u + s.light.edge_v))
            throw InputError(at + "the light's corner is not finite (values too large)");
    }
    if (a.deform == Deform::sequence) {
        s.mesh = sequence_mesh(base.mesh, a, frame);
    } else if (a.deform == Deform::wave && frame != 0) {
        const Mesh w = wave_mesh(a.wave_detail, 2.0 * M_PI * double(frame) / double(a.frames));
        std::copy(w.vertices.begin(), w.vertices.end(), s.mesh.vertices.begin());
    }
    if (!a.objects.empty()) move_objects(s.mesh, a, frame);
    if (a.deform != Deform::none || !a.objects.empty()) s.diagonal = length(s.mesh.bounds().extent());
    return s;
}

Scene scene_at_frame(const Scene& base, int frame) {
    if (base.animation) return scene_at_frame(base, *base.animation, frame);
    return scene_at_frame(base, Animation{}, frame);
}

}  // namespace raplas
