// Animated scenes: the [animation] keys (arrays of tables in ParamSet),
// keyframe interpolation, orbits, rigid motions of OBJ objects, mesh
// sequences, the built-in animations and the dump of an animated scene.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "raplas/scene/animation.hpp"
#include "raplas/scene/scene.hpp"
#include "raplas/util/bytes.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/params.hpp"
#include "run_raplas.hpp"

namespace {

using raplas::same_bits;
using raplas::same_bytes;

namespace fs = std::filesystem;
using raplas::Animation;
using raplas::Camera;
using raplas::InputError;
using raplas::Mesh;
using raplas::ParamSet;
using raplas::Scene;
using raplas::Vec3d;
using raplas::Vec3f;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::StartsWith;

bool same_camera(const Camera& a, const Camera& b) {
    return same_bits(a.eye, b.eye) && same_bits(a.look_at, b.look_at) && same_bits(a.up, b.up) &&
           same_bits(a.fov_deg, b.fov_deg);
}

bool same_mesh(const Mesh& a, const Mesh& b) {
    return a.triangles == b.triangles && same_bytes(a.vertices, b.vertices) &&
           a.triangle_material == b.triangle_material && a.triangle_object == b.triangle_object;
}

// Everything of two frames' scenes that an animation can change, byte for byte.
bool same_frame(const Scene& a, const Scene& b) {
    return same_camera(a.camera, b.camera) && same_bits(a.light.corner, b.light.corner) && same_mesh(a.mesh, b.mesh) &&
           same_bits(a.diagonal, b.diagonal);
}

void expect_near(const Vec3d& got, const Vec3d& want, double tol) {
    EXPECT_NEAR(got.x, want.x, tol);
    EXPECT_NEAR(got.y, want.y, tol);
    EXPECT_NEAR(got.z, want.z, tol);
}

// Two triangles: object "tri" (1,0,0), (0,1,0), (0,0,1) and object "other",
// which shares the corner (0,1,0) with it.
const char* const kTwoObjects =
    "v 1 0 0\nv 0 1 0\nv 0 0 1\nv -1 1 0\nv -1 2 0\n"
    "o tri\nf 1 2 3\n"
    "o other\nf 2 4 5\n";

class AnimationTest : public raplas_test::TempDirFixture {
protected:
    AnimationTest() : TempDirFixture("raplas_animation") {}
    // The scene of a scene file with this text (in the test's directory).
    Scene load(const std::string& text, const std::vector<std::string>& overrides = {}) const {
        raplas::SceneRequest req;
        req.scene_file = write("scene.toml", text);
        req.overrides = overrides;
        return raplas::load_scene(req);
    }
    // The message of the InputError that loading this scene text throws ("" if none).
    std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) const {
        try {
            load(text, overrides);
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
    std::string file(const std::string& name) const { return (dir / name).string(); }
};

const char* const kCameraKeys =
    "builtin_detail = 0\n"
    "[camera]\neye = [0, 1, 9]\nlook_at = [0, 0, 0]\nfov_deg = 35\n"
    "[animation]\nframes = 30\n"
    "[[animation.camera]]\nframe = 4\neye = [0.7, 1.1, 10.3]\nlook_at = [0.30000000000000004, 0, 0]\nfov_deg = 30\n"
    "[[animation.camera]]\nframe = 14\neye = [0.1, 0.3, 10.3]\nup = [0, 1, 0.1]\nfov_deg = 50\n"
    "[[animation.camera]]\nframe = 20\neye = [1, 2, 3]\n";

TEST_F(AnimationTest, CameraKeyframesAreExactAtTheirFramesAndHeldOutside) {
    const Scene s = load(kCameraKeys);
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(raplas::frame_count(s), 30);
    const Animation& a = *s.animation;
    ASSERT_EQ(a.camera.size(), 3u);
    // the still scene is the keys outside [animation]
    EXPECT_EQ(s.camera.eye, Vec3d(0, 1, 9));
    // at a keyframe's frame: its values as given, byte for byte
    Camera k4;
    k4.eye = {0.7, 1.1, 10.3};
    k4.look_at = {0.30000000000000004, 0, 0};
    k4.up = {0, 1, 0};
    k4.fov_deg = 30;
    EXPECT_TRUE(same_camera(raplas::scene_at_frame(s, 4).camera, k4));
    const Camera c14 = raplas::scene_at_frame(s, 14).camera;
    // (0.7 + (0.1 - 0.7) * 1 is not 0.1, nor 1.1 + (0.3 - 1.1) * 1 0.3: the keyframe, not a blend)
    EXPECT_TRUE(same_bits(c14.eye, Vec3d(0.1, 0.3, 10.3)));
    EXPECT_TRUE(same_bits(c14.up, Vec3d(0, 1, 0.1)));
    EXPECT_TRUE(same_bits(c14.look_at, Vec3d(0, 0, 0)));  // left out: the still camera's
    EXPECT_EQ(c14.fov_deg, 50.0);
    const Camera c20 = raplas::scene_at_frame(s, 20).camera;
    EXPECT_TRUE(same_bits(c20.eye, Vec3d(1, 2, 3)));
    EXPECT_EQ(c20.fov_deg, 35.0);  // the still camera's
    // held before the first keyframe and after the last
    for (int f : {0, 3}) EXPECT_TRUE(same_camera(raplas::scene_at_frame(s, f).camera, k4)) << f;
    for (int f : {21, 29}) EXPECT_TRUE(same_camera(raplas::scene_at_frame(s, f).camera, c20)) << f;
    EXPECT_FALSE(raplas::scene_at_frame(s, 0).camera_auto);
    EXPECT_FALSE(raplas::scene_at_frame(s, 0).animation) << "a frame's scene is a still scene";
}

TEST_F(AnimationTest, CameraInterpolationAtMidpoints) {
    const Scene s = load(kCameraKeys);
    // frame 9: half way from 4 to 14
    const Camera c = raplas::scene_at_frame(s, 9).camera;
    expect_near(c.eye, {0.4, 0.7, 10.3}, 1e-12);
    expect_near(c.look_at, {0.15, 0, 0}, 1e-12);
    expect_near(c.up, {0, 1, 0.05}, 1e-12);
    EXPECT_NEAR(c.fov_deg, 40.0, 1e-12);
    // frame 17: half way from 14 to 20
    const Camera d = raplas::scene_at_frame(s, 17).camera;
    expect_near(d.eye, {0.55, 1.15, 6.65}, 1e-12);
    EXPECT_NEAR(d.fov_deg, 42.5, 1e-12);
    // a quarter of the way
    const Camera q = raplas::scene_at_frame(s, 6).camera;
    expect_near(q.eye, {0.58, 0.94, 10.3}, 1e-12);
}

TEST_F(AnimationTest, LightKeyframes) {
    const Scene s = load(
        "builtin_detail = 0\n[animation]\nframes = 21\n"
        "[[animation.light]]\nframe = 0\ncorner = [-1, 4, 0.1]\n"
        "[[animation.light]]\nframe = 10\ncorner = [1.1, 2, 0.3]\n"
        "[[animation.light]]\nframe = 20\ncorner = [0.3, 2, 0.1]\n");
    EXPECT_TRUE(same_bits(raplas::scene_at_frame(s, 0).light.corner, Vec3d(-1, 4, 0.1)));
    EXPECT_TRUE(same_bits(raplas::scene_at_frame(s, 10).light.corner, Vec3d(1.1, 2, 0.3)));
    EXPECT_TRUE(same_bits(raplas::scene_at_frame(s, 20).light.corner, Vec3d(0.3, 2, 0.1)));
    expect_near(raplas::scene_at_frame(s, 5).light.corner, {0.05, 3, 0.2}, 1e-12);
    expect_near(raplas::scene_at_frame(s, 15).light.corner, {0.7, 2, 0.2}, 1e-12);
    // the edges stay the still light's
    EXPECT_EQ(raplas::scene_at_frame(s, 5).light.edge_u, s.light.edge_u);
}

TEST_F(AnimationTest, OrbitPositions) {
    const Scene s = load(
        "builtin_detail = 0\n[camera]\neye = [0, 5, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_deg = 33\n"
        "[animation]\nframes = 4\norbit.center = [1, 2, 3]\norbit.radius = 4\norbit.eye_height = 1\norbit.start_deg = 0\n");
    const Vec3d want[] = {{1, 3, 7}, {5, 3, 3}, {1, 3, -1}, {-3, 3, 3}};  // a quarter turn a frame, +z toward +x
    for (int f = 0; f < 4; ++f) {
        const Camera c = raplas::scene_at_frame(s, f).camera;
        expect_near(c.eye, want[f], 1e-12);
        EXPECT_EQ(c.look_at, Vec3d(1, 2, 3));
        EXPECT_EQ(c.up, Vec3d(0, 1, 0));
        EXPECT_EQ(c.fov_deg, 33.0);
    }
    // turns = -0.5 over 2 frames: half a turn clockwise, frame 1 at -90 degrees
    const Scene h = load(
        "builtin_detail = 0\n[animation]\nframes = 2\n[animation.orbit]\ncenter = [0, 0, 0]\nradius = 2\n"
        "eye_height = 0.5\nturns = -0.5\nstart_deg = 0\n");
    expect_near(raplas::scene_at_frame(h, 1).camera.eye, {-2, 0.5, 0}, 1e-12);
    // any orbit key alone: the still camera circles its look_at, frame 0 at the still camera
    const Scene d = load("builtin_detail = 0\n[camera]\neye = [3, 4, 4]\nlook_at = [0, 1, 0]\n[animation]\nframes = 8\n",
                         {"animation.orbit.turns=1"});
    ASSERT_TRUE(d.animation && d.animation->orbit);
    EXPECT_NEAR(d.animation->orbit->radius, 5.0, 1e-12);
    EXPECT_NEAR(d.animation->orbit->eye_height, 3.0, 1e-12);
    expect_near(raplas::scene_at_frame(d, 0).camera.eye, {3, 4, 4}, 1e-12);
    // four frames later: the other side
    expect_near(raplas::scene_at_frame(d, 4).camera.eye, {-3, 4, -4}, 1e-12);
}

TEST_F(AnimationTest, RigidMotionOfAKnownTriangle) {
    write("two.obj", kTwoObjects);
    const Scene s = load(
        "mesh = \"two.obj\"\n[camera]\neye = [0, 0, 9]\nlook_at = [0, 0, 0]\n"
        "[animation]\nframes = 11\n"
        "[[animation.object]]\nname = \"tri\"\npivot = [1, 0, 0]\n"
        "[[animation.object.keys]]\nframe = 0\n"
        "[[animation.object.keys]]\nframe = 10\ntranslate = [2, 0, 0]\naxis = [0, 2, 0]\nangle_deg = 90\nscale = 3\n");
    ASSERT_EQ(s.mesh.object_names, (std::vector<std::string>{"tri", "other"}));
    ASSERT_EQ(s.mesh.triangle_object, (std::vector<std::int32_t>{0, 1}));
    auto corner = [](const Scene& f, std::size_t t, int k) { return raplas::to_d(f.mesh.corner(t, k)); };
    // frame 10: p -> pivot + translate + R_y(90) (3 (p - pivot)), R_y(90) (x, y, z) = (z, y, -x)
    const Scene f10 = raplas::scene_at_frame(s, 10);
    expect_near(corner(f10, 0, 0), {3, 0, 0}, 1e-6);
    expect_near(corner(f10, 0, 1), {3, 3, 3}, 1e-6);
    expect_near(corner(f10, 0, 2), {6, 0, 3}, 1e-6);
    // the other object keeps its corners, the shared one too (copied for the moving triangle)
    EXPECT_EQ(corner(f10, 1, 0), Vec3d(0, 1, 0));
    EXPECT_EQ(corner(f10, 1, 1), Vec3d(-1, 1, 0));
    EXPECT_NE(f10.mesh.triangles[0][1], f10.mesh.triangles[1][0]);
    // frame 5: half way: 45 degrees, translate (1, 0, 0), scale 2
    const Scene f5 = raplas::scene_at_frame(s, 5);
    const double h = std::sqrt(0.5);
    expect_near(corner(f5, 0, 1), {2 - 2 * h, 2, 2 * h}, 1e-6);
    expect_near(corner(f5, 0, 2), {2, 0, 4 * h}, 1e-6);
    // frame 0: the first keyframe moves nothing; the mesh is the still one, byte for byte
    const Scene f0 = raplas::scene_at_frame(s, 0);
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(f0.mesh.corner(0, k), s.mesh.corner(0, k)));
    // the diagonal follows the moved mesh
    EXPECT_GT(f10.diagonal, s.diagonal);
}

TEST_F(AnimationTest, WholeMeshMotionComposesAfterTheObjects) {
    write("two.obj", kTwoObjects);
    const Scene s = load(
        "mesh = \"two.obj\"\nfloor = true\n[camera]\neye = [0, 0, 9]\nlook_at = [0, 0, 0]\n"
        "[animation]\nframes = 2\n"
        "[[animation.object]]\nname = \"*\"\nkeys = [{frame = 0}, {frame = 1, translate = [0, 10, 0]}]\n"
        "[[animation.object]]\nname = \"tri\"\nkeys = [{frame = 1, translate = [0, 0, 5]}]\n");
    const Scene f = raplas::scene_at_frame(s, 1);
    EXPECT_EQ(raplas::to_d(f.mesh.corner(0, 0)), Vec3d(1, 10, 5));
    EXPECT_EQ(raplas::to_d(f.mesh.corner(1, 1)), Vec3d(-1, 11, 0));
    // the floor (triangles 2 and 3) stays
    for (std::size_t t = 2; t < 4; ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(f.mesh.corner(t, k), s.mesh.corner(t, k));
    // a single keyframe holds for every frame
    EXPECT_EQ(raplas::to_d(raplas::scene_at_frame(s, 0).mesh.corner(0, 0)), Vec3d(1, 0, 5));
}

TEST_F(AnimationTest, RotationBetweenDifferentAxesTakesTheShorterArc) {
    write("two.obj", kTwoObjects);
    const Scene s = load(
        "mesh = \"two.obj\"\n[camera]\neye = [0, 0, 9]\nlook_at = [0, 0, 0]\n[animation]\nframes = 3\n"
        "[[animation.object]]\nname = \"tri\"\nkeys = [{frame = 0, axis = [0, 0, 1], angle_deg = 90}, "
        "{frame = 2, axis = [0, 0, -1], angle_deg = 270}]\n");
    // the two keys are the same rotation: every frame between them too
    const Scene f = raplas::scene_at_frame(s, 1);
    expect_near(raplas::to_d(f.mesh.corner(0, 0)), {0, 1, 0}, 1e-6);
    expect_near(raplas::to_d(f.mesh.corner(0, 1)), {-1, 0, 0}, 1e-6);
}

TEST_F(AnimationTest, ObjNamesAreKeptPerTriangle) {
    const Mesh m = raplas::load_obj_text(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\ng  left  \nf 2 4 3\no thing\nf 1 2 4\ng left\nf 1 3 4\n", "n.obj", "");
    EXPECT_EQ(m.object_names, (std::vector<std::string>{"", "left", "thing"}));
    EXPECT_EQ(m.triangle_object, (std::vector<std::int32_t>{0, 1, 2, 1}));
    const Mesh b = raplas::builtin_mesh(0);
    EXPECT_EQ(b.object_names, (std::vector<std::string>{"floor", "wall", "box", "big_sphere", "small_sphere"}));
    ASSERT_EQ(b.triangle_object.size(), b.triangles.size());
    EXPECT_EQ(b.triangle_object.front(), 0);
    EXPECT_EQ(b.triangle_object.back(), 4);
}

TEST_F(AnimationTest, MeshSequenceFramesAndTriangleCountMismatch) {
    const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    write("walk_0001.obj", tri);
    write("walk_0002.obj", "v 0 0 2\nv 1 0 2\nv 0 1 2\nf 1 2 3\n");
    write("walk_0003.obj", tri + "v 1 1 0\nf 2 4 3\n");
    const std::string head = "[camera]\neye = [0, 0, 9]\nlook_at = [0, 0, 0]\n[animation]\n"
                             "mesh_sequence = \"walk_%04d.obj\"\nsequence_first = 1\n";
    const Scene s = load(head + "frames = 2\n", {"floor=true"});
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(s.mesh.corner(0, 0), Vec3f(0, 0, 0));  // the still mesh is frame 0's file
    const Scene f1 = raplas::scene_at_frame(s, 1);
    EXPECT_EQ(f1.mesh.corner(0, 0), Vec3f(0, 0, 2));
    ASSERT_EQ(f1.mesh.triangles.size(), 3u);  // the floor of the still mesh comes along
    for (int k = 0; k < 3; ++k) EXPECT_EQ(f1.mesh.corner(1, k), s.mesh.corner(1, k));
    EXPECT_EQ(f1.mesh.materials[std::size_t(f1.mesh.triangle_material[2])].name, "floor");
    // a file with another triangle count: named with its frame, when the scene is loaded
    const std::string msg = error_of(head + "frames = 3\n");
    EXPECT_EQ(msg, file("walk_0003.obj") + ": frame 2 has 2 triangles, frame 0 (" + file("walk_0001.obj") +
                       ") has 1: every file of animation.mesh_sequence must have as many");
    // and when a frame is made from a file changed since
    write("walk_0002.obj", tri + "v 1 1 0\nf 2 4 3\n");
    try {
        raplas::scene_at_frame(s, 1);
        ADD_FAILURE() << "a changed triangle count was taken";
    } catch (const InputError& e) {
        EXPECT_THAT(e.what(), AllOf(HasSubstr("walk_0002.obj"), HasSubstr("frame 1 has 2 triangles")));
    }
    // a missing file: the key, the frame and the file
    EXPECT_THAT(error_of(head + "frames = 4\n"),
                AllOf(StartsWith(file("scene.toml") + ":5: animation.mesh_sequence, frame 3: mesh 'walk_0004.obj' not found")));
    // a pattern without %d, or with another field
    EXPECT_EQ(error_of("[animation]\nmesh_sequence = \"walk.obj\"\n"),
              file("scene.toml") + ":2: scene key 'animation.mesh_sequence' = 'walk.obj' has no %d (or %0Nd) for the frame number");
    EXPECT_THAT(error_of("[animation]\nmesh_sequence = \"walk_%s.obj\"\n"), HasSubstr("has '%s'"));
    EXPECT_THAT(error_of("[animation]\nmesh_sequence = \"w%d_%d.obj\"\n"), HasSubstr("more than one %d"));
    // and a mesh as well
    EXPECT_THAT(error_of("mesh = \"walk_0001.obj\"\n[animation]\nmesh_sequence = \"walk_%04d.obj\"\n"),
                HasSubstr("mesh and animation.mesh_sequence each give the mesh"));
}

TEST_F(AnimationTest, SequenceFileNames) {
    EXPECT_EQ(raplas::sequence_file_name("walk_%04d.obj", 7), "walk_0007.obj");
    EXPECT_EQ(raplas::sequence_file_name("walk_%04d.obj", 123456), "walk_123456.obj");
    EXPECT_EQ(raplas::sequence_file_name("f%d", 0), "f0");
    EXPECT_EQ(raplas::sequence_file_name("100%%/a%02d.obj", 3), "100%/a03.obj");
    for (const char* bad : {"walk.obj", "a%", "a%x.obj", "a%4d.obj", "a%00d", "%d%d", "%%d"})
        EXPECT_THROW(raplas::sequence_file_name(bad, 1), std::invalid_argument) << bad;
}

TEST_F(AnimationTest, BuiltinAnimationMovesTheBoxAndCirclesTheCamera) {
    const Scene s = load("builtin_detail = 1\n[animation]\nbuiltin = \"default\"\n");
    ASSERT_TRUE(s.animation);
    EXPECT_EQ(raplas::frame_count(s), 48);
    EXPECT_EQ(s.name, "builtin");
    const Animation& a = *s.animation;
    ASSERT_TRUE(a.orbit);
    ASSERT_EQ(a.objects.size(), 1u);
    EXPECT_EQ(a.objects[0].name, "box");
    const Scene f0 = raplas::scene_at_frame(s, 0), f12 = raplas::scene_at_frame(s, 12);
    EXPECT_TRUE(same_mesh(f0.mesh, s.mesh));
    // the box (object 2) turned a quarter turn about its pivot; the rest did not move
    const std::size_t box = std::size_t(std::find(s.mesh.triangle_object.begin(), s.mesh.triangle_object.end(), 2) -
                                        s.mesh.triangle_object.begin());
    const Vec3d p = raplas::to_d(s.mesh.corner(box, 0)) - Vec3d(0.9, 0, -0.7);
    expect_near(raplas::to_d(f12.mesh.corner(box, 0)), Vec3d(0.9 + p.z, p.y, -0.7 - p.x), 1e-6);
    EXPECT_EQ(f12.mesh.corner(0, 0), s.mesh.corner(0, 0));
    // the camera a quarter of the way round
    const Vec3d e0 = f0.camera.eye - f0.camera.look_at, e12 = f12.camera.eye - f12.camera.look_at;
    EXPECT_NEAR(std::atan2(e12.x, e12.z) - std::atan2(e0.x, e0.z), M_PI / 2, 1e-12);
    // a key given replaces the built-in animation's part: frames here
    EXPECT_EQ(raplas::frame_count(load("[animation]\nbuiltin = \"default\"\nframes = 5\n")), 5);
    EXPECT_THAT(error_of("mesh = \"x.obj\"\n[animation]\nbuiltin = \"default\"\n"),
                HasSubstr("mesh and animation.builtin each give the mesh"));
}

TEST_F(AnimationTest, BuiltinWaveDeformsTheGrid) {
    const Scene s = load("builtin_detail = 1\n[animation]\nbuiltin = \"wave\"\nframes = 8\n");
    EXPECT_EQ(s.name, "wave");
    EXPECT_EQ(s.mesh.triangles.size(), 2u * 8 * 8);
    EXPECT_EQ(s.mesh.object_names, std::vector<std::string>{"wave"});
    const Scene f0 = raplas::scene_at_frame(s, 0), f2 = raplas::scene_at_frame(s, 2);
    EXPECT_TRUE(same_mesh(f0.mesh, s.mesh));
    EXPECT_EQ(f2.mesh.triangles, s.mesh.triangles);
    // a quarter period later: y = 0.25 sin(pi x + pi z / 2 - pi / 2) at the corner (-2, -2)
    EXPECT_NEAR(f2.mesh.vertices[0].y, 0.25 * std::sin(-2 * M_PI - M_PI - M_PI / 2), 1e-6);
    EXPECT_NE(f2.mesh.vertices[0].y, s.mesh.vertices[0].y);
    for (const auto& v : f2.mesh.vertices) EXPECT_LE(std::fabs(v.y), 0.25f + 1e-6f);
}

TEST_F(AnimationTest, FramesAreDeterministic) {
    write("two.obj", kTwoObjects);
    const std::string text =
        "mesh = \"two.obj\"\nfloor = true\n[animation]\nframes = 30\norbit.turns = 0.3\n"
        "[[animation.light]]\nframe = 3\ncorner = [0, 3, 0]\n[[animation.light]]\nframe = 17\ncorner = [0.1, 2.9, 1]\n"
        "[[animation.object]]\nname = \"tri\"\npivot = [0.3, 0.1, 0]\nkeys = [{frame = 1, axis = [1, 2, 3], angle_deg = 10}, "
        "{frame = 13, axis = [0, 1, 0], angle_deg = -75.5, scale = 1.7, translate = [0.1, 0.2, 0.3]}]\n";
    const Scene a = load(text), b = load(text);
    for (int f : {0, 1, 6, 7, 13, 22, 29}) {
        const Scene x = raplas::scene_at_frame(a, f);
        EXPECT_TRUE(same_frame(x, raplas::scene_at_frame(a, f))) << "frame " << f << ", called twice";
        EXPECT_TRUE(same_frame(x, raplas::scene_at_frame(b, f))) << "frame " << f << ", loaded twice";
    }
    const Scene w = load("builtin_detail = 2\n[animation]\nbuiltin = \"wave\"\n");
    EXPECT_TRUE(same_frame(raplas::scene_at_frame(w, 17), raplas::scene_at_frame(w, 17)));
    // and frames differ where they should
    EXPECT_FALSE(same_frame(raplas::scene_at_frame(a, 6), raplas::scene_at_frame(a, 7)));
}

// p.dump() of a loaded animated scene, as --dump-scene makes it.
std::string dump_of(const ParamSet& loaded, const Scene& s) {
    ParamSet p = loaded;
    raplas::resolve_scene_params(p, s, "");
    return p.dump();
}

TEST_F(AnimationTest, DumpReloadsToTheSameAnimation) {
    write("two.obj", kTwoObjects);
    const std::vector<std::string> texts = {
        std::string("mesh = \"two.obj\"\nfloor = true\n[animation]\nframes = 12\nfps = 30\n"
                    "[[animation.camera]]\nframe = 0\nfov_deg = 20\n"
                    "[[animation.camera]]\nframe = 11\neye = [1, 2, 9]\nlook_at = [0.1, 0.2, 0.3]\n"
                    "[[animation.light]]\nframe = 5\ncorner = [1, 5, 1]\n"
                    "[[animation.object]]\nname = \"tri\"\npivot = [1, 0, 0]\n"
                    "[[animation.object.keys]]\nframe = 2\nangle_deg = 33.3\n"
                    "[[animation.object.keys]]\nframe = 9\naxis = [1, 0, 0]\nscale = 0.1\n"),
        "[animation]\nbuiltin = \"default\"\nframes = 12\n",
        "[animation]\nbuiltin = \"wave\"\norbit.turns = 2\n",
    };
    for (const std::string& text : texts) {
        SCOPED_TRACE(text);
        ParamSet p = raplas::scene_params();
        p.load_file(write("scene.toml", text));
        const Scene s = raplas::scene_from_params(p, "");
        const std::string dump = dump_of(p, s);
        ParamSet q = raplas::scene_params();
        q.load_file(write("dumped.toml", dump));
        const Scene t = raplas::scene_from_params(q, "");
        EXPECT_EQ(dump_of(q, t), dump);
        ASSERT_TRUE(t.animation);
        EXPECT_EQ(t.animation->frames, s.animation->frames);
        EXPECT_EQ(t.animation->fps, s.animation->fps);
        for (int f = 0; f < s.animation->frames; ++f)
            EXPECT_TRUE(same_frame(raplas::scene_at_frame(s, f), raplas::scene_at_frame(t, f))) << "frame " << f;
    }
}

TEST_F(AnimationTest, DumpSceneOnTheCommandLine) {
    const raplas_test::RunResult a = raplas_test::run_raplas(dir, {"render", "--set", "animation.builtin=default", "--dump-scene"});
    ASSERT_EQ(a.code, 0) << a.err;
    EXPECT_THAT(a.out, AllOf(HasSubstr("\nframes = 48\n"), HasSubstr("\n[[animation.object]]\nname = \"box\"\n"),
                             HasSubstr("\norbit.radius = 2.5\n"), HasSubstr("\nangle_deg = 360.0\n")));
    write("dumped.toml", a.out);
    const raplas_test::RunResult b = raplas_test::run_raplas(dir, {"render", "--scene", "dumped.toml", "--dump-scene"});
    ASSERT_EQ(b.code, 0) << b.err;
    EXPECT_EQ(b.out, a.out);
}

TEST_F(AnimationTest, BadKeysNameTheFileLineAndKeyPath) {
    const std::string f = file("scene.toml");
    // keyframes out of order
    EXPECT_EQ(error_of("[animation]\nframes = 9\n[[animation.camera]]\nframe = 5\n[[animation.camera]]\nframe = 5\n"),
              f + ":6: animation.camera[1].frame = 5 is not after animation.camera[0].frame = 5: keyframes must be in "
                  "increasing frame order");
    EXPECT_THAT(error_of("[[animation.object]]\nname = \"box\"\nkeys = [{frame = 3}, {frame = 1}]\n"),
                AllOf(StartsWith(f + ":3: animation.object[0].keys[1].frame = 1 is not after"), HasSubstr("increasing")));
    // frame count
    EXPECT_EQ(error_of("[animation]\nframes = 0\n"), f + ":2: scene key 'animation.frames' = 0 is out of range [1, 10000]");
    EXPECT_EQ(error_of("[animation]\nframes = 10001\n"),
              f + ":2: scene key 'animation.frames' = 10001 is out of range [1, 10000]");
    // NaN and infinity in a transform
    EXPECT_EQ(error_of("[[animation.object]]\nname = \"box\"\n[[animation.object.keys]]\ntranslate = [0, nan, 0]\n"),
              f + ":4: scene key 'animation.object[0].keys[0].translate' must have finite components");
    EXPECT_EQ(error_of("[[animation.object]]\nname = \"box\"\n[[animation.object.keys]]\nangle_deg = inf\n"),
              f + ":4: scene key 'animation.object[0].keys[0].angle_deg' must be finite");
    // an unknown key in a keyframe: its whole path, and the nearest key
    EXPECT_EQ(error_of("[[animation.camera]]\nframe = 1\nfov = 3\n"),
              f + ":3: unknown scene key 'animation.camera[0].fov' (did you mean 'animation.camera[0].fov_deg'?)");
    EXPECT_EQ(error_of("[[animation.light]]\nframe = 1\ncolour = 3\n"),
              f + ":3: unknown scene key 'animation.light[0].colour' (a table of animation.light takes frame, corner)");
    // a keyframe without its frame, a light keyframe without its corner
    EXPECT_EQ(error_of("[animation]\nframes = 2\n\n[[animation.camera]]\neye = [1, 2, 3]\n"),
              f + ":4: animation.camera[0] has no frame");
    EXPECT_EQ(error_of("[[animation.light]]\nframe = 1\n"), f + ":1: animation.light[0] has no corner");
    // a table where an array of tables belongs
    EXPECT_EQ(error_of("[animation.camera]\nframe = 1\n"),
              f + ":1: scene key 'animation.camera' must be an array of tables ([[animation.camera]], or [{...}, {...}])");
    // an object the mesh does not have
    EXPECT_EQ(error_of("builtin_detail = 0\n[[animation.object]]\nname = \"bxo\"\nkeys = [{frame = 0}]\n"),
              f + ":3: animation.object[0].name = 'bxo': <builtin:default> has no object or group of that name (did you "
                  "mean 'box'?)");
    EXPECT_THAT(error_of("builtin_detail = 0\n[[animation.object]]\nname = \"box\"\n"), HasSubstr("has no keys"));
    EXPECT_THAT(error_of("builtin_detail = 0\n[[animation.object]]\nname = \"box\"\nkeys = [{frame = 0, axis = [0, 0, 0]}]\n"),
                HasSubstr("animation.object[0].keys[0].axis is zero"));
    // a degenerate keyframe camera, and the camera path and orbit together
    EXPECT_EQ(error_of("builtin_detail = 0\n[[animation.camera]]\nframe = 1\neye = [0, 0, 0]\nlook_at = [0, 0, 0]\n"),
              f + ":2: animation.camera[0]: the camera's eye equals look_at");
    EXPECT_EQ(error_of("builtin_detail = 0\n[animation]\norbit.turns = 1\n[[animation.camera]]\nframe = 1\n"),
              f + ":3: give animation.camera keyframes or animation.orbit, not both");
    // --set takes keyframes inline and names the option
    EXPECT_EQ(error_of("", {"animation.camera=[{frame = 2}, {frame = 1}]"}),
              "--set animation.camera: animation.camera[1].frame = 1 is not after animation.camera[0].frame = 2: "
              "keyframes must be in increasing frame order");
}

TEST_F(AnimationTest, FramesOutsideTheAnimationAndDegenerateCamerasBetweenKeys) {
    const Scene s = load(
        "builtin_detail = 0\n[animation]\nframes = 3\n"
        "[[animation.camera]]\nframe = 0\neye = [0, 1, 5]\nlook_at = [0, 1, -5]\n"
        "[[animation.camera]]\nframe = 2\neye = [0, 1, -5]\nlook_at = [0, 1, 5]\n");
    EXPECT_THROW(raplas::scene_at_frame(s, 3), InputError);
    EXPECT_THROW(raplas::scene_at_frame(s, -1), InputError);
    try {
        raplas::scene_at_frame(s, 1);
        ADD_FAILURE() << "eye = look_at at frame 1 was taken";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "animation: frame 1: the camera's eye equals look_at");
    }
    // a still scene has frame 0 alone
    const Scene still = load("builtin_detail = 0\n");
    EXPECT_FALSE(still.animation);
    EXPECT_EQ(raplas::frame_count(still), 1);
    EXPECT_TRUE(same_frame(raplas::scene_at_frame(still, 0), still));
    EXPECT_THROW(raplas::scene_at_frame(still, 1), InputError);
}

}  // namespace
