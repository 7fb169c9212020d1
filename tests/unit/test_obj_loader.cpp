// OBJ/MTL loading and its line-numbered validation.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "raplas/scene/mesh.hpp"
#include "raplas/util/error.hpp"
#include "temp_dir.hpp"
#include "shared_scenes.hpp"

namespace {

namespace fs = std::filesystem;
using raplas::InputError;
using raplas::Mesh;
using raplas::Vec3f;
using ::testing::AllOf;
using ::testing::HasSubstr;

class ObjLoader : public raplas_test::TempDirFixture {
protected:
    ObjLoader() : TempDirFixture("raplas_obj") {}
    // Message of the InputError load_obj throws; fails the test if none.
    static std::string load_error(const std::string& path) {
        try {
            raplas::load_obj(path);
        } catch (const InputError& e) {
            return e.what();
        } catch (const std::exception& e) {
            ADD_FAILURE() << "not an InputError: " << e.what();
            return "";
        }
        ADD_FAILURE() << path << " loaded without error";
        return "";
    }
};

const char* kThreeVerts = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

double area(const Mesh& m, std::size_t t) {
    const raplas::Vec3d a = raplas::to_d(m.corner(t, 0)), b = raplas::to_d(m.corner(t, 1)),
                        c = raplas::to_d(m.corner(t, 2));
    return 0.5 * raplas::length(raplas::cross(b - a, c - a));
}

TEST_F(ObjLoader, QuadIsSplitIntoTwoTrianglesAlongItsShorterDiagonal) {
    // diagonal 1-3 is shorter: (0,1,3), (1,2,3)
    const std::string p = write("quad.obj",
                                "# a kite\n"
                                "o quad\n"
                                "v 0 0 0\n"
                                "v 2 0 0\n"
                                "v 3 3 0\n"
                                "v 0 2 0\n"
                                "f 1 2 3 4\n");
    Mesh m = raplas::load_obj(p);
    EXPECT_EQ(m.source, p);
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_EQ(m.vertices[2], Vec3f(3, 3, 0));
    ASSERT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 3}));
    EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{1, 2, 3}));
    EXPECT_DOUBLE_EQ(area(m, 0) + area(m, 1), 6.0);
    ASSERT_EQ(m.triangle_material.size(), 2u);
    EXPECT_EQ(m.triangle_material[0], 0);  // default material
    ASSERT_FALSE(m.materials.empty());
    const raplas::Aabb b = m.bounds();
    EXPECT_EQ(b.lo.x, 0.0);
    EXPECT_EQ(b.hi.y, 3.0);

    // diagonal 0-2 is shorter: (0,1,2), (0,2,3)
    const std::string q = write("quad2.obj", "v 0 0 0\nv 3 0 0\nv 1 1 0\nv 0 3 0\nf 1 2 3 4\n");
    Mesh n = raplas::load_obj(q);
    ASSERT_EQ(n.triangle_count(), 2u);
    EXPECT_EQ(n.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
    EXPECT_EQ(n.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
    EXPECT_DOUBLE_EQ(area(n, 0) + area(n, 1), 3.0);
}

TEST_F(ObjLoader, PentagonRelativeIndicesSlashesAndCrlf) {
    const std::string p = write("poly.obj",
                                "v 0 0 0\r\n"
                                "v 2 0 0\r\n"
                                "v 3 1 0\r\n"
                                "v 1 2 0\r\n"
                                "v -1 1 0\r\n"
                                "vt 0 0\r\n"
                                "vn 0 0 1\r\n"
                                "f -5/1/1 -4/1/1 -3/1/1 -2/1/1 -1/1/1\r\n"
                                "f 1//1 2//1 3//1\r\n");
    Mesh m = raplas::load_obj(p);
    ASSERT_EQ(m.triangle_count(), 4u);  // 3 from the pentagon, 1 more
    EXPECT_EQ(m.vertices[4], Vec3f(-1, 1, 0));
    // the pentagon's triangles cover it exactly (area 5) and use only its corners
    EXPECT_DOUBLE_EQ(area(m, 0) + area(m, 1) + area(m, 2), 5.0);
    for (std::size_t t = 0; t < 3; ++t)
        for (auto v : m.triangles[t]) EXPECT_LT(v, 5u);
    EXPECT_EQ(m.triangles[3], (std::array<std::uint32_t, 3>{0, 1, 2}));
}

TEST_F(ObjLoader, MaterialsKdAndKe) {
    write("scene.mtl",
          "newmtl red\n"
          "Kd 0.8 0.1 0.2\n"
          "\n"
          "newmtl lamp\n"
          "Kd 0 0 0\n"
          "Ke 5 4 3\n");
    const std::string p = write("scene.obj",
                                "mtllib scene.mtl\n"
                                "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                "f 1 2 3\n"
                                "usemtl lamp\n"
                                "f 2 4 3\n"
                                "usemtl red\n"
                                "f 1 2 4\n");
    Mesh m = raplas::load_obj(p);
    ASSERT_EQ(m.triangle_count(), 3u);
    ASSERT_EQ(m.triangle_material.size(), 3u);
    const auto& before = m.materials.at(std::size_t(m.triangle_material[0]));
    const auto& lamp = m.materials.at(std::size_t(m.triangle_material[1]));
    const auto& red = m.materials.at(std::size_t(m.triangle_material[2]));
    EXPECT_EQ(m.triangle_material[0], 0);  // before any usemtl: the default
    EXPECT_EQ(before.emission, Vec3f(0, 0, 0));
    EXPECT_EQ(lamp.name, "lamp");
    EXPECT_EQ(lamp.diffuse, Vec3f(0, 0, 0));
    EXPECT_EQ(lamp.emission, Vec3f(5, 4, 3));
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.diffuse, Vec3f(0.8f, 0.1f, 0.2f));
    EXPECT_EQ(red.emission, Vec3f(0, 0, 0));
}

TEST_F(ObjLoader, MissingFile) {
    const std::string p = (dir / "does_not_exist.obj").string();
    EXPECT_THAT(load_error(p), HasSubstr(p));
}

TEST_F(ObjLoader, EmptyFile) {
    const std::string p = write("empty.obj", "");
    EXPECT_THAT(load_error(p), AllOf(HasSubstr(p), HasSubstr("empty")));
}

TEST_F(ObjLoader, BinaryGarbage) {
    std::string junk = "v 0 0 0\n";
    for (int i = 0; i < 256; ++i) junk.push_back(char((i * 37) & 0xff));
    junk += std::string("\0\0\0\0", 4);
    const std::string p = write("garbage.obj", junk);
    EXPECT_THAT(load_error(p), HasSubstr(p));
    // a single NUL in an otherwise valid file
    const std::string q = write("nul.obj", std::string(kThreeVerts) + std::string("f 1 2 3\0\n", 9));
    EXPECT_THAT(load_error(q), AllOf(HasSubstr(q), HasSubstr("NUL")));
}

TEST_F(ObjLoader, NonFiniteCoordinatesNameTheirLine) {
    struct Case {
        const char* line;
        const char* name;
    };
    const Case cases[] = {{"v nan 0 0", "nan"},          {"v 0 NaN 0", "NaN"},     {"v 0 0 inf", "inf"},
                          {"v -inf 0 0", "-inf"},        {"v 1e39 0 0", "1e39"},   {"v 0 -1e39 0", "-1e39"},
                          {"v 0 0 infinity", "infinity"}, {"v 0 0 1e400", "1e400"}, {"v 0.5 abc 0", "abc"},
                          {"v 1 2", "got 2"},    {"vn 0 nan 1", "nan"},    {"vt inf 0", "inf"}};
    for (const Case& c : cases) {
        // the bad line is line 4 (after a comment and two vertices)
        const std::string p =
            write("bad.obj", std::string("# header\nv 0 0 0\nv 1 0 0\n") + c.line + "\nv 0 1 0\nf 1 2 3\n");
        EXPECT_THAT(load_error(p), AllOf(HasSubstr(p + ":4:"), HasSubstr(c.name))) << c.line;
    }
    // large but finite float values load
    const std::string ok = write("big.obj", "v 1e30 0 0\nv 0 1e-30 0\nv 0 0 -2.5e37\nf 1 2 3\n");
    Mesh m = raplas::load_obj(ok);
    EXPECT_EQ(m.vertices[0].x, 1e30f);
    EXPECT_EQ(m.vertices[2].z, -2.5e37f);
}

// Found by fuzzing: tinyobjloader's number parser overflows an int on an
// exponent of ten or more digits, in the OBJ and in the MTL alike.
TEST_F(ObjLoader, HugeExponentsAreRejectedInObjAndMtl) {
    const std::string obj = write("exp.obj", std::string(kThreeVerts) + "v 1e0000000000000000001 0 2e9999999999\nf 1 2 3\n");
    EXPECT_THAT(load_error(obj), AllOf(HasSubstr(obj + ":4:"), HasSubstr("2e9999999999"), HasSubstr("exponent")));
    write("exp.mtl", "newmtl m\nKd 0.5 0.5 1e-12345678901\n");
    const std::string withmtl = write("mtl.obj", std::string("mtllib exp.mtl\nusemtl m\n") + kThreeVerts + "f 1 2 3\n");
    EXPECT_THAT(load_error(withmtl), AllOf(HasSubstr("exp.mtl:2:"), HasSubstr("1e-12345678901")));
    // nine exponent digits, and any number of leading zeros, still load
    const std::string ok = write("ok.obj", "v 1e-000000000000001 0 0\nv 0 1e-000000009 0\nv 0 0 1\nf 1 2 3\n");
    Mesh m = raplas::load_obj(ok);
    EXPECT_EQ(m.vertices[0].x, 0.1f);
}

TEST_F(ObjLoader, UnusedElementsAreIgnoredWhateverTheirNumbers) {
    // Skin weights, lines, points and tags are not triangles: raplas skips
    // them, whatever numbers they hold (tinyobjloader would convert a joint id
    // of 1.9e19 to int and size a tag from an unchecked count).
    const std::string obj = write("skip.obj", std::string(kThreeVerts) +
                                                  "vw 0 19223400000000000000 1\n"
                                                  "t crease 2000000000/0/0 1\n"
                                                  "l 1 -2147483648\n  p 2147483647\n"
                                                  "f 1 2 3\nv 0 0 nan\n");
    // lines after them are still validated, under their own numbers
    EXPECT_THAT(load_error(obj), HasSubstr(obj + ":9:"));
    const std::string ok = write("skipok.obj", std::string(kThreeVerts) + "vw 0 1e19 1\nl 1 2\nf 1 2 3\n");
    const Mesh m = raplas::load_obj(ok);
    ASSERT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.corner(0, 1), Vec3f(1, 0, 0));
}

TEST_F(ObjLoader, FaceIndexErrorsNameTheirLine) {
    struct Case {
        const char* face;
        const char* what;
    };
    const Case cases[] = {
        {"f 1 2 4", "index 4"},        // out of range (3 vertices so far)
        {"f 1 2 99999999", "99999999"},
        {"f 0 1 2", "'0'"},            // OBJ indices start at 1
        {"f 1 0 2", "'0'"},
        {"f -4 -1 -2", "index -4"},    // negative beyond the start
        {"f -1 -2 -100", "-100"},
        {"f 1 2 x", "'x'"},
        {"f 1 2 3.5", "3.5"},
        {"f 1/1 2/1 3/1", "texture index 1"},   // no vt defined
        {"f 1//2 2//2 3//2", "normal index 2"},  // no vn defined
        {"f 1 2", "2 vertices"},
        {"f 1", "1 vertices"},
        {"f", "0 vertices"},
    };
    for (const Case& c : cases) {
        const std::string p = write("faces.obj", std::string("v 0 0 0\n# c\nv 1 0 0\nv 0 1 0\n\n") + c.face + "\n");
        EXPECT_THAT(load_error(p), AllOf(HasSubstr(p + ":6:"), HasSubstr(c.what))) << c.face;
    }
    // a later bad face after good ones: its own line
    const std::string p = write("later.obj", std::string(kThreeVerts) + "f 1 2 3\nf 3 2 1\nf 1 2 5\n");
    EXPECT_THAT(load_error(p), HasSubstr(p + ":6:"));
    // a forward reference to a vertex defined later is out of range where it appears
    const std::string q = write("forward.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\nv 0 1 0\n");
    EXPECT_THAT(load_error(q), HasSubstr(q + ":3:"));
    // in-range negative indices are fine
    const std::string r = write("neg.obj", std::string(kThreeVerts) + "f -3 -2 -1\n");
    EXPECT_EQ(raplas::load_obj(r).triangle_count(), 1u);
}

TEST_F(ObjLoader, NoFaces) {
    const std::string p = write("nofaces.obj", std::string("# only points\n") + kThreeVerts);
    EXPECT_THAT(load_error(p), AllOf(HasSubstr(p), HasSubstr("no faces")));
    const std::string q = write("comments.obj", "# nothing\n\n   \n# at all\n");
    EXPECT_THAT(load_error(q), HasSubstr(q));
}

TEST_F(ObjLoader, ErrorMessagesAreOneLine) {
    for (const std::string& text : {std::string(""), std::string(kThreeVerts) + "f 1 2 9\n",
                                    std::string("v nan 0 0\n"), std::string(kThreeVerts)}) {
        const std::string p = write("one.obj", text);
        const std::string msg = load_error(p);
        EXPECT_FALSE(msg.empty());
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST_F(ObjLoader, SharedCornellBoxLoads) {
    const std::string p = raplas_test::shared_scene("cornell/CornellBox-Original.obj");
    RAPLAS_NEED_SHARED(p);
    Mesh m = raplas::load_obj(p);
    EXPECT_EQ(m.triangle_count(), 36u);
    bool emissive = false;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const auto& mt = m.materials.at(std::size_t(m.triangle_material[t]));
        emissive = emissive || mt.emission.x > 0;
    }
    EXPECT_TRUE(emissive);  // the light material has Ke
}

}  // namespace
