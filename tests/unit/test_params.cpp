// ParamSet (declared, validated TOML parameters) and scene files.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "raplas/scene/scene.hpp"
#include "config.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/nearest.hpp"
#include "raplas/util/params.hpp"
#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using raplas::InputError;
using raplas::ParamSet;
using raplas::Vec3d;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

class ParamsTest : public raplas_test::TempDirFixture {
protected:
    ParamsTest() : TempDirFixture("raplas_params") {}
    static ParamSet make() {
        ParamSet p("test");
        p.add_int("count", 4, 1, 100, "an integer 1..100");
        p.add_real("scale", 1.5, 0.0, 10.0, "a real 0..10");
        p.add_bool("flag", false, "a flag");
        p.add_string("mode", std::string("fast"), "a choice", {"fast", "slow", "two words"});
        p.add_string("label", std::nullopt, "free text, optional");
        p.add_vec3("pos", std::nullopt, "optional vector");
        p.add_vec3("dir", Vec3d(0, 1, 0), "vector with default");
        p.add_int("sec.n", 7, -5, 5000, "in a section");
        p.add_real("sec.x", 0.25, -1e9, 1e9, "in a section");
        return p;
    }
    // The message of the InputError that f throws ("" if none).
    template <class F>
    static std::string error_of(F&& f) {
        try {
            f();
        } catch (const InputError& e) {
            return e.what();
        }
        return "";
    }
};

TEST_F(ParamsTest, DefaultsAndFileValues) {
    ParamSet p = make();
    EXPECT_EQ(p.get_int("count"), 4);
    EXPECT_EQ(p.get_real("scale"), 1.5);
    EXPECT_FALSE(p.get_bool("flag"));
    EXPECT_EQ(p.get_string("mode"), "fast");
    EXPECT_EQ(p.get_string("label"), "");
    EXPECT_FALSE(p.get_vec3("pos").has_value());
    EXPECT_EQ(*p.get_vec3("dir"), Vec3d(0, 1, 0));
    EXPECT_FALSE(p.is_given("count"));
    EXPECT_EQ(p.origin("count"), "default");

    const std::string f = write("a.toml",
                                "# comment\n"
                                "count = 9\n"
                                "scale = 3\n"             // an integer is a valid real
                                "flag = true\n"
                                "mode = \"slow\"\n"
                                "pos = [1, -2.5, 3e2]\n"
                                "\n"
                                "[sec]\n"
                                "n = -5\n"
                                "x = 1e8\n");
    p.load_file(f);
    EXPECT_EQ(p.get_int("count"), 9);
    EXPECT_EQ(p.get_real("scale"), 3.0);
    EXPECT_TRUE(p.get_bool("flag"));
    EXPECT_EQ(p.get_string("mode"), "slow");
    ASSERT_TRUE(p.get_vec3("pos").has_value());
    EXPECT_EQ(*p.get_vec3("pos"), Vec3d(1, -2.5, 300));
    EXPECT_EQ(p.get_int("sec.n"), -5);
    EXPECT_EQ(p.get_real("sec.x"), 1e8);
    EXPECT_TRUE(p.is_given("count"));
    EXPECT_FALSE(p.is_given("label"));
    EXPECT_EQ(p.origin("count"), f + ":2");
    EXPECT_EQ(p.origin("sec.n"), f + ":9");
    EXPECT_EQ(p.file_dir(), dir.string());
}

TEST_F(ParamsTest, DottedKeysAndInlineTablesAreTheSameKeys) {
    ParamSet p = make();
    p.load_text("sec.n = 11\n", "inline");
    EXPECT_EQ(p.get_int("sec.n"), 11);
    p.load_text("sec = { x = -2.0 }\n", "inline");
    EXPECT_EQ(p.get_real("sec.x"), -2.0);
}

TEST_F(ParamsTest, UnknownKeyNamesFileLineAndKey) {
    ParamSet p = make();
    const std::string f = write("u.toml", "count = 3\n\ncolour = 5\n");
    std::string msg = error_of([&] { p.load_file(f); });
    EXPECT_THAT(msg, AllOf(HasSubstr(f + ":3"), HasSubstr("'colour'"), HasSubstr("unknown")));
    // no key is near 'colour', and this set names no command that lists them: nothing more
    EXPECT_EQ(msg, f + ":3: unknown test key 'colour'");
    // a set that names one points there
    ParamSet listed = make();
    listed.listed_by("raplas test --dump");
    EXPECT_EQ(error_of([&] { listed.load_file(f); }), f + ":3: unknown test key 'colour' (raplas test --dump lists the keys)");
    // a near key is named instead of the list
    const std::string near = write("n.toml", "cuont = 3\n");
    EXPECT_EQ(error_of([&] { listed.load_file(near); }), near + ":1: unknown test key 'cuont' (did you mean 'count'?)");
    // in a section: the full dotted key
    const std::string g = write("s.toml", "[sec]\nn = 1\nnn = 2\n");
    msg = error_of([&] { make().load_file(g); });
    EXPECT_THAT(msg, AllOf(HasSubstr(g + ":3"), HasSubstr("'sec.nn'")));
    // a section that does not exist
    const std::string h = write("t.toml", "count = 1\n[nosuch]\nz = 1\n");
    msg = error_of([&] { make().load_file(h); });
    EXPECT_THAT(msg, AllOf(HasSubstr(h + ":3"), HasSubstr("'nosuch.z'")));
}

TEST_F(ParamsTest, WrongTypesAreRejectedWithFileLineAndKey) {
    struct Case {
        const char* text;
        const char* key;
        int line;
    };
    const Case cases[] = {
        {"count = \"three\"\n", "count", 1},
        {"\ncount = 2.5\n", "count", 2},           // a real is not an integer
        {"count = true\n", "count", 1},
        {"scale = \"big\"\n", "scale", 1},
        {"scale = false\n", "scale", 1},
        {"scale = [1, 2, 3]\n", "scale", 1},
        {"flag = 1\n", "flag", 1},
        {"flag = \"true\"\n", "flag", 1},
        {"mode = 5\n", "mode", 1},
        {"mode = [\"fast\"]\n", "mode", 1},
        {"pos = [1, 2]\n", "pos", 1},
        {"pos = [1, 2, 3, 4]\n", "pos", 1},
        {"pos = [1, \"a\", 3]\n", "pos", 1},
        {"pos = 3\n", "pos", 1},
        {"pos = [1, true, 3]\n", "pos", 1},
        {"count = 1\n\n\n[sec]\nn = \"x\"\n", "sec.n", 5},
    };
    for (const Case& c : cases) {
        const std::string f = write("w.toml", c.text);
        ParamSet p = make();
        const std::string msg = error_of([&] { p.load_file(f); });
        EXPECT_THAT(msg, AllOf(HasSubstr(f + ":" + std::to_string(c.line) + ":"),
                               HasSubstr("'" + std::string(c.key) + "'"), HasSubstr("must")))
            << c.text;
    }
}

TEST_F(ParamsTest, OutOfRangeAndBadChoicesAreRejected) {
    struct Case {
        const char* text;
        const char* key;
    };
    const Case cases[] = {
        {"count = 0\n", "count"},       {"count = 101\n", "count"},     {"count = -1\n", "count"},
        {"scale = -0.001\n", "scale"},  {"scale = 10.5\n", "scale"},    {"scale = inf\n", "scale"},
        {"scale = nan\n", "scale"},     {"sec.n = 5001\n", "sec.n"},    {"mode = \"medium\"\n", "mode"},
        {"pos = [1, inf, 0]\n", "pos"}, {"pos = [nan, 0, 0]\n", "pos"},
    };
    for (const Case& c : cases) {
        const std::string f = write("r.toml", c.text);
        ParamSet p = make();
        const std::string msg = error_of([&] { p.load_file(f); });
        EXPECT_THAT(msg, AllOf(HasSubstr(f + ":1:"), HasSubstr("'" + std::string(c.key) + "'"))) << c.text;
    }
    // the limits themselves are accepted
    ParamSet p = make();
    p.load_text("count = 1\nscale = 0.0\n", "lim");
    p.load_text("count = 100\nscale = 10\n", "lim");
    EXPECT_EQ(p.get_int("count"), 100);
    EXPECT_EQ(p.get_real("scale"), 10.0);
    // and the message says what the range is
    EXPECT_THAT(error_of([&] { p.load_text("count = 500\n", "lim"); }),
                AllOf(HasSubstr("out of range"), HasSubstr("100")));
    EXPECT_THAT(error_of([&] { p.load_text("mode = \"x\"\n", "lim"); }), HasSubstr("two words"));
}

TEST_F(ParamsTest, BadFilesAreRejectedWithTheirName) {
    ParamSet p = make();
    const std::string missing = (dir / "missing.toml").string();
    EXPECT_THAT(error_of([&] { p.load_file(missing); }), HasSubstr(missing));
    const std::string syntax = write("syntax.toml", "count = 1\nscale = = 2\n");
    EXPECT_THAT(error_of([&] { p.load_file(syntax); }), HasSubstr(syntax + ":2"));
    const std::string dup = write("dup.toml", "count = 1\ncount = 2\n");
    EXPECT_THAT(error_of([&] { p.load_file(dup); }), HasSubstr(dup + ":2"));
    const std::string bin = write("bin.toml", std::string("count = 1\n\0\0\x01\x02", 14));
    EXPECT_THAT(error_of([&] { p.load_file(bin); }), HasSubstr(bin));
    // a directory is not an (empty) file
    const std::string sub = (dir / "sub.toml").string();
    fs::create_directory(sub);
    EXPECT_THAT(error_of([&] { p.load_file(sub); }), HasSubstr(sub));
    // an empty file is valid: every key keeps its default
    const std::string empty = write("empty.toml", "");
    p.load_file(empty);
    EXPECT_EQ(p.get_int("count"), 4);
    // an error after valid lines still names its own line
    ParamSet q = make();
    const std::string partial = write("partial.toml", "count = 50\nbogus = 1\n");
    EXPECT_THAT(error_of([&] { q.load_file(partial); }), AllOf(HasSubstr(partial + ":2"), HasSubstr("'bogus'")));
}

// Found by fuzzing: toml++ recursed once per level of a dotted key or table
// header and overflowed the stack at a few thousand levels.
TEST_F(ParamsTest, DeeplyNestedKeysAreRefusedNotCrashed) {
    ParamSet p = make();
    std::string deep = "count = 5\n[a";
    for (int i = 0; i < 20000; ++i) deep += ".a";
    deep += "]\n";
    const std::string header = write("deep.toml", deep);
    EXPECT_THAT(error_of([&] { p.load_file(header); }), AllOf(HasSubstr(header + ":2"), HasSubstr("nested too deeply")));
    std::string dotted = "x";
    for (int i = 0; i < 5000; ++i) dotted += ".x";
    EXPECT_THAT(error_of([&] { p.set(dotted + "=1"); }), HasSubstr("unknown"));
    EXPECT_THAT(error_of([&] { p.set("sec.n = {" + dotted + " = 1}"); }), HasSubstr("nested too deeply"));
    // dots in comments do not count
    const std::string commented = write("comment.toml", "# " + std::string(5000, '.') + "\ncount = 6\n");
    p.load_file(commented);
    EXPECT_EQ(p.get_int("count"), 6);
}

TEST_F(ParamsTest, SetOverrides) {
    ParamSet p = make();
    p.set("count=42");
    EXPECT_EQ(p.get_int("count"), 42);
    EXPECT_EQ(p.origin("count"), "--set count");
    EXPECT_TRUE(p.is_given("count"));
    p.set("scale=2.25");
    EXPECT_EQ(p.get_real("scale"), 2.25);
    p.set("scale=7");  // integer literal for a real key
    EXPECT_EQ(p.get_real("scale"), 7.0);
    p.set("scale=1e-3");
    EXPECT_EQ(p.get_real("scale"), 1e-3);
    p.set("flag=true");
    EXPECT_TRUE(p.get_bool("flag"));
    p.set("mode=slow");  // bare word is a string
    EXPECT_EQ(p.get_string("mode"), "slow");
    p.set("mode=\"fast\"");  // quoted TOML string
    EXPECT_EQ(p.get_string("mode"), "fast");
    p.set("mode=two words");  // bare words with a space
    EXPECT_EQ(p.get_string("mode"), "two words");
    p.set("label=hello");
    EXPECT_EQ(p.get_string("label"), "hello");
    p.set("pos=[1, 2, 3]");
    EXPECT_EQ(*p.get_vec3("pos"), Vec3d(1, 2, 3));
    p.set("pos=[-0.5,1e3,7]");
    EXPECT_EQ(*p.get_vec3("pos"), Vec3d(-0.5, 1000, 7));
    p.set("sec.n=4999");
    EXPECT_EQ(p.get_int("sec.n"), 4999);
    // --set wins over an earlier file value
    const std::string f = write("o.toml", "count = 3\n");
    ParamSet q = make();
    q.load_file(f);
    q.set("count=5");
    EXPECT_EQ(q.get_int("count"), 5);
}

TEST(Nearest, DamerauLevenshteinDistance) {
    using raplas::edit_distance;
    EXPECT_EQ(edit_distance("", ""), 0u);
    EXPECT_EQ(edit_distance("", "abc"), 3u);
    EXPECT_EQ(edit_distance("abc", ""), 3u);
    EXPECT_EQ(edit_distance("paper", "paper"), 0u);
    EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
    EXPECT_EQ(edit_distance("fgpa", "fpga"), 1u);  // two neighbours swapped: one edit
    EXPECT_EQ(edit_distance("image.witdh", "image.width"), 1u);
    EXPECT_EQ(edit_distance("icc.psi_pipe", "icc.psi_pipes"), 1u);
    EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // optimal string alignment: a swapped pair is not edited again
}

TEST(Nearest, NamesWithinTheLimitPrefixesAfterThem) {
    using raplas::nearest_names;
    using V = std::vector<std::string>;
    EXPECT_EQ(raplas::near_limit(4), 1u);
    EXPECT_EQ(raplas::near_limit(8), 2u);
    EXPECT_EQ(raplas::near_limit(40), 3u);
    EXPECT_EQ(nearest_names("papr", {"fpga", "paper"}), V{"paper"});
    EXPECT_EQ(nearest_names("fgpa", {"fpga", "paper"}), V{"fpga"});
    EXPECT_EQ(nearest_names("zzzz", {"fpga", "paper"}), V{});
    EXPECT_EQ(nearest_names("papers", {"paper", "pacer"}), V{"paper"});  // the closest only
    EXPECT_EQ(nearest_names("fov", {"fov_deg", "eye"}), V{"fov_deg"});     // a beginning
    EXPECT_EQ(nearest_names("fo", {"fov_deg"}), V{});                     // too short to be one
    EXPECT_EQ(nearest_names("fo", {"fov_deg", "f"}), V{"f"});
    EXPECT_EQ(nearest_names("fov", {"fov_deg", "fox"}), V{"fox"});       // a typo before a beginning
    EXPECT_EQ(nearest_names("ab", {"ac", "bb", "ax", "ay"}, 2), (V{"ac", "bb"}));
    EXPECT_EQ(raplas::did_you_mean({}), "");
    EXPECT_EQ(raplas::did_you_mean({"a"}), " (did you mean 'a'?)");
    EXPECT_EQ(raplas::did_you_mean({"a", "b", "c"}), " (did you mean 'a', 'b' or 'c'?)");
}

TEST_F(ParamsTest, UnknownKeysNameTheNearestKnownOnes) {
    ParamSet p = raplas::scene_params();
    auto msg = [&](const std::string& a) { return error_of([&] { p.set(a); }); };
    EXPECT_EQ(msg("image.witdh=8"), "--set: unknown scene key 'image.witdh' (did you mean 'image.width'?)");
    EXPECT_EQ(msg("camera.fov=30"), "--set: unknown scene key 'camera.fov' (did you mean 'camera.fov_deg'?)");
    // the last part against the known keys' last parts: the right key in another section
    EXPECT_EQ(msg("camera.width=8"), "--set: unknown scene key 'camera.width' (did you mean 'image.width'?)");
    EXPECT_EQ(msg("shadow_sise=4"), "--set: unknown scene key 'shadow_sise' (did you mean 'groups.shadow_size'?)");
    // nothing near: the command that lists the keys
    EXPECT_EQ(msg("image.colour=red"), "--set: unknown scene key 'image.colour' (raplas render --dump-scene lists the keys)");
}

TEST_F(ParamsTest, BareLeafNamesTheOneKeyEndingInIt) {
    ParamSet p = make();
    p.set("n=12");  // sec.n
    EXPECT_EQ(p.get_int("sec.n"), 12);
    EXPECT_EQ(p.origin("sec.n"), "--set sec.n");
    p.set("x=0.5");
    EXPECT_EQ(p.get_real("sec.x"), 0.5);
    // a wrong value names the whole key
    EXPECT_EQ(error_of([&] { p.set("n=9999"); }), "--set sec.n: test key 'sec.n' = 9999 is out of range [-5, 5000]");
    // only bare words: a dotted key must be whole
    EXPECT_THAT(error_of([&] { p.set("ec.n=1"); }), HasSubstr("unknown test key 'ec.n'"));
    // several keys end in it: the error names them all
    ParamSet q("test");
    q.add_int("a.size", 1, 0, 9, "").add_int("b.size", 1, 0, 9, "").add_int("size_x", 1, 0, 9, "");
    EXPECT_EQ(error_of([&] { q.set("size=3"); }), "--set: 'size' could be 'a.size' or 'b.size'; give the whole key");
    EXPECT_EQ(q.get_int("a.size"), 1);
    // files take whole keys only
    const std::string f = write("leaf.toml", "n = 3\n");
    EXPECT_EQ(error_of([&] { make().load_file(f); }), f + ":1: unknown test key 'n' (did you mean 'sec.n'?)");
}

TEST_F(ParamsTest, RouteAssignmentAcrossConfigAndSceneKeys) {
    const ParamSet mp = raplas::model::machine_params();
    const ParamSet sp = raplas::scene_params();
    using R = std::pair<std::size_t, std::string>;
    auto route = [&](const std::string& a) { return raplas::route_assignment(a, {&mp, &sp}); };
    auto msg = [&](const std::string& a) { return error_of([&] { route(a); }); };
    EXPECT_EQ(route("name=x"), R(0, "name=x"));  // in both: the first set's
    EXPECT_EQ(route("image.width=8"), R(1, "image.width=8"));
    EXPECT_EQ(route("width=8"), R(1, "image.width=8"));
    EXPECT_EQ(route("rti_pipes=2"), R(0, "icc.rti_pipes=2"));
    EXPECT_EQ(route("triangle_depth =7"), R(0, "fifo.triangle_depth=7"));
    EXPECT_EQ(msg("triangles_per_sphere=1"),
              "--set: 'triangles_per_sphere' could be 'workload.triangles_per_sphere' or "
              "'spheres.triangles_per_sphere'; give the whole key");
    // suggestions from both sets
    EXPECT_EQ(msg("icc.psi_pipe=3"), "--set: unknown config or scene key 'icc.psi_pipe' (did you mean 'icc.psi_pipes'?)");
    EXPECT_EQ(msg("image.hieght=3"), "--set: unknown config or scene key 'image.hieght' (did you mean 'image.height'?)");
    EXPECT_EQ(msg("fifo.depth=4"),
              "--set: unknown config or scene key 'fifo.depth' (raplas simulate --dump-config and raplas render "
              "--dump-scene list the keys)");
    EXPECT_THAT(msg("rti_pipes"), HasSubstr("expected key=value"));
}

TEST_F(ParamsTest, RealsPrintAsWritten) {
    ParamSet p("real");
    p.add_real("tiny", 1e-4, 1e-6, 1e6, "").add_real("big", 2.5e9, 0.0, 1e12, "").add_real("clock", 400.0, 1.0, 1e5, "");
    const std::string text = p.dump();
    EXPECT_THAT(text, HasSubstr("tiny = 0.0001\n"));
    EXPECT_THAT(text, HasSubstr("big = 2.5e9\n"));
    EXPECT_THAT(text, HasSubstr("clock = 400.0\n"));
    EXPECT_EQ(error_of([&] { p.set("tiny=0"); }), "--set tiny: real key 'tiny' = 0.0 is out of range [1e-6, 1e6]");
    EXPECT_EQ(error_of([&] { p.set("clock=1e9"); }), "--set clock: real key 'clock' = 1e9 is out of range [1.0, 100000.0]");
    // every default of the shipped key sets: no '+' or leading zero in an exponent, and it reads back
    for (ParamSet set : {raplas::model::machine_params(), raplas::scene_params()}) {
        const std::string dump = set.dump();
        EXPECT_EQ(dump.find("e+"), std::string::npos) << dump;
        EXPECT_EQ(dump.find("e-0"), std::string::npos) << dump;
        ParamSet back = set;
        back.load_text(dump, "dump");
        EXPECT_EQ(back.dump(), dump);
    }
}

TEST_F(ParamsTest, BadSetOverridesNameTheKey) {
    ParamSet p = make();
    EXPECT_THAT(error_of([&] { p.set("nosuch=1"); }), AllOf(HasSubstr("--set"), HasSubstr("'nosuch'")));
    EXPECT_THAT(error_of([&] { p.set("sec.nosuch=1"); }), HasSubstr("'sec.nosuch'"));
    EXPECT_THAT(error_of([&] { p.set("count"); }), AllOf(HasSubstr("--set"), HasSubstr("key=value")));
    EXPECT_THAT(error_of([&] { p.set("=3"); }), HasSubstr("key=value"));
    EXPECT_THAT(error_of([&] { p.set("count=abc"); }), AllOf(HasSubstr("'count'"), HasSubstr("integer")));
    EXPECT_THAT(error_of([&] { p.set("count=2.5"); }), HasSubstr("'count'"));
    EXPECT_THAT(error_of([&] { p.set("count=1000"); }), AllOf(HasSubstr("'count'"), HasSubstr("out of range")));
    EXPECT_THAT(error_of([&] { p.set("scale=-1"); }), AllOf(HasSubstr("'scale'"), HasSubstr("out of range")));
    EXPECT_THAT(error_of([&] { p.set("scale=fast"); }), HasSubstr("'scale'"));
    EXPECT_THAT(error_of([&] { p.set("flag=yes"); }), HasSubstr("'flag'"));
    EXPECT_THAT(error_of([&] { p.set("mode=medium"); }), AllOf(HasSubstr("'mode'"), HasSubstr("medium")));
    EXPECT_THAT(error_of([&] { p.set("pos=[1,2]"); }), HasSubstr("'pos'"));
    EXPECT_THAT(error_of([&] { p.set("pos=1,2,3"); }), HasSubstr("'pos'"));
    // failed overrides leave the value alone
    EXPECT_EQ(p.get_int("count"), 4);
    EXPECT_EQ(p.get_real("scale"), 1.5);
    EXPECT_FALSE(p.get_vec3("pos").has_value());
}

TEST_F(ParamsTest, DumpParsesBackToTheSameValues) {
    ParamSet p = make();
    p.set("count=77");
    p.set("scale=0.1");  // needs 17 digits to round-trip exactly
    p.set("flag=true");
    p.set("mode=two words");
    p.set("label=quote \" and backslash \\ and tab \t end");
    p.set("dir=[0.30000000000000004, -1e-300, 123456789.125]");
    p.set("sec.x=-987654.321");
    const std::string text = p.dump();
    // awkward reals print as valid TOML that reads back bit-exactly
    for (const char* lit : {"100", "1e20", "-0.0", "5e-324", "1.7976931348623157e308", "123456789.0", "2.5e-7", "-3",
                            "0.30000000000000004"}) {
        const double x = std::strtod(lit, nullptr);
        ParamSet r("real");
        r.add_real("x", 0.0, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), "any real");
        r.set(std::string("x=") + lit);
        ASSERT_EQ(r.get_real("x"), x) << lit;
        ParamSet back("real");
        back.add_real("x", 1.0, -std::numeric_limits<double>::max(), std::numeric_limits<double>::max(), "any real");
        back.load_text(r.dump(), "dump");
        EXPECT_EQ(back.get_real("x"), x) << r.dump();
        EXPECT_EQ(std::signbit(back.get_real("x")), std::signbit(x)) << r.dump();
    }
    ParamSet q = make();
    q.load_text(text, "dump");
    for (const std::string& k : p.keys()) EXPECT_TRUE(q.has(k)) << k;
    EXPECT_EQ(q.get_int("count"), 77);
    EXPECT_EQ(q.get_real("scale"), 0.1);
    EXPECT_TRUE(q.get_bool("flag"));
    EXPECT_EQ(q.get_string("mode"), "two words");
    EXPECT_EQ(q.get_string("label"), p.get_string("label"));
    EXPECT_EQ(*q.get_vec3("dir"), *p.get_vec3("dir"));
    EXPECT_EQ(q.get_real("sec.x"), -987654.321);
    EXPECT_EQ(q.get_int("sec.n"), 7);
    // an unset optional stays unset (it is printed as a comment)
    EXPECT_FALSE(q.get_vec3("pos").has_value());
    EXPECT_FALSE(q.is_given("pos"));
    EXPECT_EQ(q.get_string("label"), "quote \" and backslash \\ and tab \t end");
    // and dumping again gives the same text
    EXPECT_EQ(q.dump(), text);
    // descriptions are in the dump
    EXPECT_THAT(text, HasSubstr("an integer 1..100"));
}

TEST_F(ParamsTest, SceneParamsDumpRoundTrips) {
    ParamSet p = raplas::scene_params();
    p.set("image.width=33");
    p.set("camera.eye=[1, 2, 3]");
    p.set("camera.look_at=[0, 0.5, 0]");
    p.set("spheres.method=file-order");
    p.set("shading.shadow_offset=0.003");
    const std::string text = p.dump();
    ParamSet q = raplas::scene_params();
    const std::string f = write("scene_dump.toml", text);
    q.load_file(f);
    EXPECT_EQ(q.dump(), text);
    EXPECT_EQ(q.get_int("image.width"), 33);
    EXPECT_EQ(*q.get_vec3("camera.eye"), Vec3d(1, 2, 3));
    EXPECT_EQ(q.get_string("spheres.method"), "file-order");
    EXPECT_EQ(q.get_real("shading.shadow_offset"), 0.003);
    EXPECT_FALSE(q.get_vec3("light.corner").has_value());
    EXPECT_EQ(q.get_string("mesh"), "");
}

TEST_F(ParamsTest, ArraysOfTablesReadInlineOrAsHeadersAndDumpBack) {
    ParamSet key("t");
    key.add_int("frame", 0, 0, 100, "frame").add_real("v", 1.0, -10.0, 10.0, "a value");
    ParamSet item("t");
    item.add_string("name", std::nullopt, "a name").add_tables("keys", key, "keys");
    ParamSet p("t");
    p.add_int("n", 1, 0, 9, "n").add_tables("sec.items", item, "items");
    EXPECT_TRUE(p.get_tables("sec.items").empty());
    p.load_text("n = 2\n[[sec.items]]\nname = \"a\"\n[[sec.items.keys]]\nframe = 3\n[[sec.items.keys]]\nframe = 4\nv = -2.5\n"
                "[[sec.items]]\nname = \"b\"\nkeys = [{frame = 7}]\n",
                "f.toml");
    const auto& items = p.get_tables("sec.items");
    ASSERT_EQ(items.size(), 2u);
    EXPECT_EQ(items[0].item_path(), "sec.items[0]");
    EXPECT_EQ(items[1].item_origin(), "f.toml:9");
    EXPECT_EQ(items[0].get_tables("keys")[1].get_real("v"), -2.5);
    EXPECT_EQ(items[0].get_tables("keys")[1].origin("v"), "f.toml:8");
    EXPECT_EQ(items[1].get_tables("keys")[0].get_int("frame"), 7);
    EXPECT_EQ(p.value_text("sec.items"),
              "[{name = \"a\", keys = [{frame = 3, v = 1.0}, {frame = 4, v = -2.5}]}, {name = \"b\", keys = [{frame = 7, v = 1.0}]}]");
    const std::string dump = p.dump();
    EXPECT_THAT(dump, HasSubstr("[[sec.items]]\nname = \"a\"\n[[sec.items.keys]]\nframe = 3\nv = 1.0\n"));
    ParamSet q = p;
    q.load_text(dump, "dump");
    EXPECT_EQ(q.dump(), dump);
    // --set replaces the whole array
    q.set("sec.items=[{name = \"c\"}]");
    ASSERT_EQ(q.get_tables("sec.items").size(), 1u);
    EXPECT_EQ(q.get_tables("sec.items")[0].get_string("name"), "c");
    EXPECT_TRUE(q.get_tables("sec.items")[0].get_tables("keys").empty());
    // an unknown key in a table names its whole path and the keys a table takes; a table alone is no array
    EXPECT_EQ(error_of([&] { q.load_text("[[sec.items]]\n[[sec.items.keys]]\nframe = 1\ncolour = 2\n", "g.toml"); }),
              "g.toml:4: unknown t key 'sec.items[0].keys[0].colour' (a table of sec.items[0].keys takes frame, v)");
    EXPECT_EQ(error_of([&] { q.set("sec.items={name = \"x\"}"); }),
              "--set sec.items: t key 'sec.items' must be an array of tables ([[sec.items]], or [{...}, {...}])");
    EXPECT_EQ(error_of([&] { q.set("sec.items=[{keys = [{frame = 101}]}]"); }),
              "--set sec.items: t key 'sec.items[0].keys[0].frame' = 101 is out of range [0, 100]");
    // failed loads leave the array alone
    EXPECT_EQ(q.get_tables("sec.items")[0].get_string("name"), "c");
}

TEST_F(ParamsTest, OptionalRealsAreUnsetUntilGiven) {
    ParamSet p("t");
    p.add_optional_real("r", -1.0, 1.0, "an optional real");
    EXPECT_FALSE(p.get_optional_real("r").has_value());
    EXPECT_THAT(p.dump(), HasSubstr("# r = (unset)\n"));
    p.set("r=0.25");
    EXPECT_EQ(p.get_optional_real("r"), 0.25);
    EXPECT_EQ(error_of([&] { p.set("r=2"); }), "--set r: t key 'r' = 2.0 is out of range [-1.0, 1.0]");
    ParamSet q("t");
    q.add_optional_real("r", -1.0, 1.0, "an optional real");
    q.load_text(p.dump(), "dump");
    EXPECT_EQ(q.get_optional_real("r"), 0.25);
}

// A file of many keyframes: neither a decimal point nor a table header is a
// level of nesting, and thousands of them load; dotted keys still count.
TEST_F(ParamsTest, NumbersAndTableHeadersAreNotNesting) {
    ParamSet key("t");
    key.add_int("frame", 0, 0, 100000, "frame").add_vec3("corner", std::nullopt, "corner");
    ParamSet p = make();
    p.add_tables("sec.keys", key, "keyframes");
    std::string text = "count = 5\n";
    for (int f = 0; f < 3000; ++f) text += "[[sec.keys]]\nframe = " + std::to_string(f) + "\ncorner = [0.5, 4.25, -0.125]\n";
    p.load_text(text, "many.toml");
    EXPECT_EQ(p.get_tables("sec.keys").size(), 3000u);
    const std::string dump = p.dump();
    ParamSet back = p;
    back.load_text(dump, "dump");
    EXPECT_EQ(back.dump(), dump);
    std::string deep = "a";
    for (int i = 0; i < 1100; ++i) deep += ".a";
    std::string header = "[a";
    for (int i = 0; i < 65; ++i) header += ".a";
    for (const std::string& bad : {deep + " = 1\n", "[" + deep + "]\n", header + "]\n", "x = [\n[{" + deep + " = 1}]]\n"})
        EXPECT_THAT(error_of([&] { make().load_text(bad, "deep.toml"); }), HasSubstr("nested too deeply")) << bad.substr(0, 20);
}

// ---- scene files -------------------------------------------------------------

TEST_F(ParamsTest, SceneFileCameraEyeWithoutLookAtIsAnError) {
    const std::string f = write("cam.toml", "name = \"x\"\n[camera]\neye = [1, 2, 3]\n");
    raplas::SceneRequest req;
    req.scene_file = f;
    const std::string msg = error_of([&] { raplas::load_scene(req); });
    EXPECT_THAT(msg, AllOf(HasSubstr(f + ":3"), HasSubstr("camera.eye"), HasSubstr("camera.look_at")));
    // look_at alone too
    const std::string g = write("cam2.toml", "[camera]\n\nlook_at = [0, 0, 0]\n");
    req.scene_file = g;
    EXPECT_THAT(error_of([&] { raplas::load_scene(req); }), AllOf(HasSubstr(g + ":3"), HasSubstr("camera.eye")));
    // both: fine
    const std::string h = write("cam3.toml", "[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\n");
    req.scene_file = h;
    raplas::Scene s = raplas::load_scene(req);
    EXPECT_EQ(s.camera.eye, Vec3d(0, 1, 5));
    EXPECT_EQ(s.camera.look_at, Vec3d(0, 0, 0));
    EXPECT_FALSE(s.camera_auto);
    // eye == look_at
    const std::string k = write("cam4.toml", "[camera]\neye = [1, 1, 1]\nlook_at = [1, 1, 1]\n");
    req.scene_file = k;
    EXPECT_THAT(error_of([&] { raplas::load_scene(req); }), HasSubstr(k + ":2"));
}

TEST_F(ParamsTest, SceneImageSizeLimits) {
    for (const char* bad : {"0", "100000", "-4"}) {
        const std::string f = write("img.toml", std::string("[image]\nwidth = ") + bad + "\n");
        raplas::SceneRequest req;
        req.scene_file = f;
        EXPECT_THAT(error_of([&] { raplas::load_scene(req); }), AllOf(HasSubstr(f + ":2"), HasSubstr("image.width")))
            << bad;
        raplas::SceneRequest over;
        over.overrides = {std::string("image.height=") + bad};
        EXPECT_THAT(error_of([&] { raplas::load_scene(over); }), HasSubstr("image.height")) << bad;
    }
    // within each limit but too many pixels in total
    raplas::SceneRequest big;
    big.overrides = {"image.width=16384", "image.height=16384"};
    EXPECT_THAT(error_of([&] { raplas::load_scene(big); }), HasSubstr("image"));
    // a valid size is taken
    raplas::SceneRequest ok;
    ok.overrides = {"image.width=21", "image.height=13", "builtin_detail=0"};
    raplas::Scene s = raplas::load_scene(ok);
    EXPECT_EQ(s.width, 21);
    EXPECT_EQ(s.height, 13);
}

TEST_F(ParamsTest, SceneFileValuesReachTheScene) {
    write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string f = write("full.toml",
                                "name = \"demo\"\n"
                                "mesh = \"tri.obj\"\n"  // relative to the scene file's directory
                                "[image]\nwidth = 24\nheight = 12\n"
                                "[groups]\nsize = 8\nshadow_size = 4\n"
                                "[spheres]\ntriangles_per_sphere = 3\nmethod = \"file-order\"\n"
                                "[light]\ncorner = [0, 5, 0]\nedge_u = [1, 0, 0]\nedge_v = [0, 0, 1]\n");
    raplas::SceneRequest req;
    req.scene_file = f;
    req.overrides = {"groups.size=5"};
    raplas::Scene s = raplas::load_scene(req);
    EXPECT_EQ(s.name, "demo");
    EXPECT_EQ(s.mesh.triangle_count(), 1u);
    EXPECT_EQ(s.width, 24);
    EXPECT_EQ(s.height, 12);
    EXPECT_EQ(s.group_size, 5);
    EXPECT_EQ(s.shadow_group_size, 4);
    EXPECT_EQ(s.tris_per_sphere, 3);
    EXPECT_EQ(s.sphere_method, "file-order");
    EXPECT_EQ(s.light.corner, Vec3d(0, 5, 0));
    EXPECT_FALSE(s.light_auto);
    EXPECT_TRUE(s.camera_auto);  // no camera given: framed automatically
    // light given partially
    const std::string g = write("light.toml", "[light]\ncorner = [0, 5, 0]\n");
    req.scene_file = g;
    req.overrides.clear();
    EXPECT_THAT(error_of([&] { raplas::load_scene(req); }), HasSubstr("light"));
    // missing mesh names the mesh
    const std::string h = write("nomesh.toml", "mesh = \"no_such_mesh_file.obj\"\n");
    req.scene_file = h;
    EXPECT_THAT(error_of([&] { raplas::load_scene(req); }), HasSubstr("no_such_mesh_file.obj"));
    // both a scene and a mesh
    raplas::SceneRequest both;
    both.scene_file = f;
    both.mesh_file = (dir / "tri.obj").string();
    EXPECT_THAT(error_of([&] { raplas::load_scene(both); }), AllOf(HasSubstr("--scene"), HasSubstr("--mesh")));
}

}  // namespace

namespace {

// Corners of the mesh's first `tris` triangles in the camera's normalised image coordinates:
// the largest of |x| / tan(horizontal half-angle) and |y| / tan(vertical half-angle), and the
// smallest depth in front of the eye.
struct Framing {
    double extent = 0, min_depth = 1e300;
};
Framing framing(const raplas::Mesh& m, std::size_t tris, const raplas::Camera& cam, double aspect) {
    using namespace raplas;
    const Vec3d w = normalize(cam.eye - cam.look_at), u = normalize(cross(cam.up, w)), v = cross(w, u);
    const double tv = std::tan(cam.fov_deg * M_PI / 360.0), th = tv * aspect;
    Framing f;
    for (std::size_t t = 0; t < tris; ++t)
        for (auto i : m.triangles[t]) {
            const Vec3d q = to_d(m.vertices[i]) - cam.eye;
            const double depth = -dot(q, w);
            f.min_depth = std::min(f.min_depth, depth);
            f.extent = std::max({f.extent, std::fabs(dot(q, u)) / depth / th, std::fabs(dot(q, v)) / depth / tv});
        }
    return f;
}

TEST(AutoCamera, EveryCornerIsInViewAndTheMeshReachesTheBorder) {
    using namespace raplas;
    // A small box on a wide floor (flat: seen from higher up), and the box alone (compact).
    Mesh m;
    auto quad = [&](Vec3f a, Vec3f b, Vec3f c, Vec3f d) {
        const auto base = std::uint32_t(m.vertices.size());
        m.vertices.insert(m.vertices.end(), {a, b, c, d});
        m.triangles.push_back({base, base + 1, base + 2});
        m.triangles.push_back({base, base + 2, base + 3});
        m.triangle_material.insert(m.triangle_material.end(), {0, 0});
    };
    quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
    quad({0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1});
    quad({0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1});
    const std::size_t box = m.triangles.size();
    quad({-9, 0, -9}, {9, 0, -9}, {9, 0, 9}, {-9, 0, 9});
    for (const double aspect : {1.0, 16.0 / 9.0, 0.5})
        for (const std::size_t tris : {box, m.triangles.size()}) {
            SCOPED_TRACE("aspect " + std::to_string(aspect) + ", triangles " + std::to_string(tris));
            const Camera cam = auto_camera(m, tris, 40.0, aspect);
            const Framing f = framing(m, tris, cam, aspect);
            EXPECT_GT(f.min_depth, 0.0);
            EXPECT_LE(f.extent, 1.0) << "a corner is outside the view";
            EXPECT_GE(f.extent, 0.95) << "the mesh does not reach the border (a 2 % margin): not framed tightly";
            // Only the triangles asked for count (the floor of a scene is left out of the framing).
            if (tris == box) {
                EXPECT_GT(framing(m, m.triangles.size(), cam, aspect).extent, 1.0);
            }
        }
    // The flat scene is seen from higher up than the compact one.
    const Camera low = auto_camera(m, box, 40.0, 1.0), high = auto_camera(m, m.triangles.size(), 40.0, 1.0);
    auto elevation = [](const Camera& c) {
        const Vec3d d = normalize(c.eye - c.look_at);
        return std::asin(d.y);
    };
    EXPECT_NEAR(elevation(low) * 180 / M_PI, 17.7, 0.1);
    EXPECT_GT(elevation(high), elevation(low) + 0.2);
}

}  // namespace
