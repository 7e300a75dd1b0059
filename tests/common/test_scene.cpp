// Scene schema: defaults, types, ranges, unknown keys, overrides, styles, resolved echo.
#include <gtest/gtest.h>

#include "common/schema.hpp"
#include "common/status.hpp"

using common::InputError;
using common::Scene;
using common::Schema;

namespace {

Schema demo_schema() {
  Schema s("demo");
  s.add_real("time.end", 1e-3, "s", 0.0, 1e9, "end time", true);
  s.add_int("output.every", 10, 1, 1000000, "steps between outputs");
  s.add_bool("viscosity.enabled", false, "artificial viscosity");
  s.add_choice("shape", std::string("ugimp"), {"ugimp", "linear"}, "shape functions");
  s.add_vec3("gravity", Eigen::Vector3d(0, 0, -9.81), "m/s^2", -1e3, 1e3, "uniform gravity");
  s.add_real("courant", std::nullopt, "1", 0.0, 1.0, "Courant number", true);
  Schema& body = s.add_table_array("body", "bodies", 1, 10);
  body.add_real("radius", std::nullopt, "m", 0.0, 1e6, "radius", true);
  body.add_vec3("velocity", Eigen::Vector3d::Zero(), "m/s", -1e5, 1e5, "initial velocity");
  body.add_choice("model", std::string("elastic"), {}, "material model");
  Schema elastic, till;
  elastic.add_real("youngs_modulus", 1e9, "Pa", 0.0, 1e13, "E", true);
  till.add_real("a", 2.67e10, "Pa", 0.0, 1e13, "Tillotson A", true);
  body.add_style_switch("model", {{"elastic", elastic}, {"tillotson", till}});
  return s;
}

const char* kGood = R"(
courant = 0.3
[time]
end = 2
[[body]]
radius = 5
[[body]]
radius = 1
model = "tillotson"
a = 1e10
)";

std::string error_of(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    Scene::parse(demo_schema(), text, "scene.toml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Scene, DefaultsAndValues) {
  Scene s = Scene::parse(demo_schema(), kGood, "scene.toml");
  EXPECT_DOUBLE_EQ(s.real("time.end"), 2.0);  // integer normalised to real
  EXPECT_EQ(s.integer("output.every"), 10);
  EXPECT_FALSE(s.boolean("viscosity.enabled"));
  EXPECT_EQ(s.string("shape"), "ugimp");
  EXPECT_DOUBLE_EQ(s.vec3("gravity")[2], -9.81);
  EXPECT_TRUE(s.given("courant"));
  EXPECT_FALSE(s.given("shape"));
  ASSERT_EQ(s.count("body"), 2u);
  Scene b0 = s.element("body", 0), b1 = s.element("body", 1);
  EXPECT_DOUBLE_EQ(b0.real("radius"), 5.0);
  EXPECT_DOUBLE_EQ(b0.real("youngs_modulus"), 1e9);  // style default
  EXPECT_FALSE(b0.has("a"));
  EXPECT_DOUBLE_EQ(b1.real("a"), 1e10);
  EXPECT_TRUE(b1.given("a"));
  EXPECT_FALSE(b1.given("velocity"));
  EXPECT_THROW(b1.real("youngs_modulus"), InputError);
}

TEST(Scene, ResolvedTomlRoundTrips) {
  Scene s = Scene::parse(demo_schema(), kGood, "scene.toml");
  Scene again = Scene::parse(demo_schema(), s.to_toml(), "echo");
  EXPECT_EQ(again.to_toml(), s.to_toml());
  EXPECT_DOUBLE_EQ(again.element("body", 1).real("a"), 1e10);
  EXPECT_NE(s.to_toml().find("youngs_modulus"), std::string::npos);  // defaults are echoed
}

TEST(Scene, UnknownKeyNamesFileKeyAndSuggestion) {
  const std::string e = error_of(std::string(kGood) + "\n[output]\nevry = 3\n");
  EXPECT_NE(e.find("scene.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("output.evry"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'output.every'"), std::string::npos) << e;
}

TEST(Scene, StyleKeyRejectedUnderOtherStyle) {
  const std::string e = error_of("courant=0.1\n[[body]]\nradius=1\na=3.0\n");
  EXPECT_NE(e.find("body[0].a"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
}

TEST(Scene, WrongTypesAndRanges) {
  EXPECT_NE(error_of("courant = \"fast\"\n[[body]]\nradius=1\n").find("expected a number"), std::string::npos);
  const std::string r = error_of("courant = 1.5\n[[body]]\nradius=1\n");
  EXPECT_NE(r.find("courant"), std::string::npos) << r;
  EXPECT_NE(r.find("(0, 1]"), std::string::npos) << r;
  EXPECT_NE(error_of("courant = 0\n[[body]]\nradius=1\n").find("out of range"), std::string::npos);  // exclusive min
  EXPECT_NE(error_of("courant=0.1\nshape=\"cubic\"\n[[body]]\nradius=1\n").find("\"ugimp\", \"linear\""), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\ngravity=[1,2]\n[[body]]\nradius=1\n").find("3 numbers"), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\n[output]\nevery=1.5\n[[body]]\nradius=1\n").find("integer"), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\nviscosity.enabled=1\n[[body]]\nradius=1\n").find("true or false"), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\n[[body]]\nradius=nan\n").find("out of range"), std::string::npos);
}

TEST(Scene, RequiredAndCounts) {
  EXPECT_NE(error_of("[[body]]\nradius=1\n").find("courant: required key is missing"), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\n").find("between 1 and 10"), std::string::npos);
  EXPECT_NE(error_of("courant=0.1\nbody = 3\n").find("array of tables"), std::string::npos);
}

TEST(Scene, SyntaxErrorNamesLine) {
  const std::string e = error_of("courant = 0.1\n[[body]\n");
  EXPECT_NE(e.find("scene.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("line 2"), std::string::npos) << e;
}

TEST(Scene, Overrides) {
  Scene s = Scene::parse(demo_schema(), kGood, "scene.toml",
                         {"time.end=0.5", "body[0].velocity=[0,0,-5000]",
                          "shape=linear"});
  EXPECT_DOUBLE_EQ(s.real("time.end"), 0.5);
  EXPECT_DOUBLE_EQ(s.element("body", 0).vec3("velocity")[2], -5000.0);
  EXPECT_EQ(s.string("shape"), "linear");
  // body[1] switched to elastic while still carrying the tillotson key `a`: rejected.
  EXPECT_THROW(Scene::parse(demo_schema(), kGood, "scene.toml", {"body[1].model=elastic"}), InputError);
  // Appending a body by index == count.
  Scene t = Scene::parse(demo_schema(), kGood, "s", {"body[2].radius=7"});
  EXPECT_EQ(t.count("body"), 3u);
  EXPECT_NE(error_of(kGood, {"body[5].radius=7"}).find("out of range"), std::string::npos);
  EXPECT_NE(error_of(kGood, {"novalue"}).find("key=value"), std::string::npos);
  EXPECT_NE(error_of(kGood, {"time.end=-1"}).find("time.end"), std::string::npos);
}

TEST(Scene, HelpListsEveryKey) {
  const std::string h = demo_schema().help_text();
  for (const char* k : {"time.end", "output.every", "courant", "REQUIRED", "[[body]]", "youngs_modulus",
                        "when body[i].model = \"tillotson\"", "[m/s^2]"})
    EXPECT_NE(h.find(k), std::string::npos) << k;
}
