// Animated scenes (docs/SCENES.md, "Animation"): the [animation] keys of a
// scene file give a frame count and rate, a camera path (keyframes or an
// orbit), rigid motions of the mesh's objects, a moving light and a deforming
// mesh (a numbered OBJ sequence or the built-in wave). scene_at_frame() makes
// the still scene of one frame. Frames are numbered 0 .. frames - 1; every
// value at a frame is computed from the keys alone, in doubles, the same way
// every time (no state, no threads).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "raplas/scene/scene.hpp"

namespace raplas {

constexpr int kMaxFrames = 10000;

// A camera keyframe: the still camera with the fields the keyframe gives.
struct CameraKey {
    int frame = 0;
    Camera camera;
};

// The camera circling `center` about the vertical (+y) axis, looking at it:
// at frame f of F its eye is center + (radius sin a, eye_height, radius cos a)
// with a = start_deg + 360 turns f / F degrees (so frame F would be frame 0
// again); up and field of view are the still camera's.
struct Orbit {
    Vec3d center;
    double radius = 1, eye_height = 0, turns = 1, start_deg = 0;
};

struct ObjectKey {
    int frame = 0;
    Vec3d translate{0, 0, 0};
    Vec3d axis{0, 1, 0};  // rotation axis, as given (any non-zero length)
    double angle_deg = 0;
    double scale = 1;
};

// A rigid motion (with uniform scale) of one object of the mesh, or of the
// whole mesh ("*"): a point p goes to pivot + translate + R (scale (p - pivot)),
// R the rotation by angle_deg about axis.
struct ObjectTrack {
    std::string name;
    Vec3d pivot{0, 0, 0};
    std::vector<ObjectKey> keys;  // in increasing frame order
    std::int32_t object = -1;     // index into the mesh's object_names; -1 for "*"
};

// A rigid motion with a uniform scale, in the form the animation applies to
// an object (ObjectTrack): a point p goes to
// pivot + translate + R (scale (p - pivot)), R the rotation matrix r.
struct RigidMotion {
    Vec3d pivot{0, 0, 0}, translate{0, 0, 0};
    double scale = 1;
    bool rotates = false;  // r is used (else R is the identity)
    double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

    // In double, with the animation's order of operations.
    Vec3d apply(const Vec3d& p) const {
        if (!rotates && scale == 1) return p + translate;
        Vec3d d = (p - pivot) * scale;
        if (rotates)
            d = {r[0][0] * d.x + r[0][1] * d.y + r[0][2] * d.z, r[1][0] * d.x + r[1][1] * d.y + r[1][2] * d.z,
                 r[2][0] * d.x + r[2][1] * d.y + r[2][2] * d.z};
        return pivot + d + translate;
    }
    // No motion at all: apply() returns p itself.
    bool identity() const { return !rotates && scale == 1 && translate == Vec3d(0, 0, 0); }
};

// Track `track`'s motion at `frame`: what scene_at_frame() applies to the
// track's vertices (in doubles, each corner then rounded to float). At a
// keyframe its values as given; between two, translate and scale linear, the
// angle linear about one axis, else the rotations spherically interpolated.
RigidMotion motion_at(const ObjectTrack& track, int frame);

struct LightKey {
    int frame = 0;
    Vec3d corner;
};

enum class Deform { none, sequence, wave };

struct Animation {
    int frames = 1;
    double fps = 24;
    std::vector<CameraKey> camera;  // in increasing frame order; empty: no camera keyframes
    std::optional<Orbit> orbit;     // never together with camera keyframes
    std::vector<ObjectTrack> objects;
    std::vector<LightKey> light;  // keyframes of the light's corner
    Deform deform = Deform::none;
    std::vector<std::string> sequence_files;  // mesh_sequence: the OBJ file of each frame
    int wave_detail = 3;                      // wave: builtin_detail of the grid

    // Anything that changes from frame to frame, or more than one frame.
    bool animated() const {
        return frames > 1 || !camera.empty() || orbit || !objects.empty() || !light.empty() || deform != Deform::none;
    }
};

// The [animation] scene keys (scene_params() declares them).
void add_animation_params(ParamSet& p);
// Whether a file or --set gave any of them.
bool animation_keys_given(const ParamSet& p);

// The animation the keys give; `still` is the scene of the keys outside
// [animation] (what keyframes leave out is its camera's and light's, object
// names are its mesh's). Reads every file of a mesh sequence to check that
// it exists and has the still mesh's triangle count. Throws InputError naming
// the file and line (or --set) and the key.
Animation animation_from_params(const ParamSet& p, const Scene& still);

// The mesh the [animation] keys give the still scene instead of `mesh`:
// frame 0's file of animation.mesh_sequence, or the built-in wave; nullopt
// when they give none. `mesh_override` is --mesh (refused with either).
std::optional<Mesh> animation_still_mesh(const ParamSet& p, const std::string& mesh_override);
// The OBJ files of animation.mesh_sequence, one per frame, found as `mesh`
// is (InputError when one is missing); none without a sequence.
std::vector<std::string> animation_mesh_files(const ParamSet& p);

// Writes what the animation resolved by itself into `p` (the frame count and
// rate, the orbit's values, the built-in animation's keys), so that p.dump()
// is a scene file that gives the same animation.
void resolve_animation_params(ParamSet& p, const Animation& a);

// The number of frames of a scene: 1 for a still scene.
int frame_count(const Scene& s);

// The still scene of `frame` (0 <= frame < a.frames): camera, light and mesh
// of that frame, its diagonal recomputed; the result has no animation. At a
// keyframe's frame the keyframe's values are taken as they are (no
// interpolation). Throws InputError for a frame outside the animation, a
// camera that degenerates between keyframes, a vertex moved out of the float
// range, or a sequence file that has changed since the scene was loaded.
Scene scene_at_frame(const Scene& base, const Animation& a, int frame);
// Same, with the scene's own animation (a still scene has frame 0 only).
Scene scene_at_frame(const Scene& base, int frame);

// The camera of `frame`: keyframes or orbit, else `still`.
Camera camera_at_frame(const Animation& a, const Camera& still, int frame);

// The file name of number `n` in a sequence pattern: its one %d (or %0Nd,
// zero-padded to N digits) replaced by n, %% by %. std::invalid_argument
// saying what is wrong when the pattern has no such field or another one.
std::string sequence_file_name(const std::string& pattern, long long n);

}  // namespace raplas
