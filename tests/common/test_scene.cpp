/// @file test_scene.cpp
/// Scene schema: defaults, types, ranges, unknown keys, overrides, styles, resolved echo,
/// deprecated aliases and typed choices.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <array>
#include <sstream>

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

// ---- deprecated aliases (Schema::add_alias) ----

namespace {

/// Collects what spdlog writes while alive (the default logger is restored at scope exit).
class LogCapture {
 public:
  LogCapture() : old_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out_);
    spdlog::set_default_logger(std::make_shared<spdlog::logger>("capture", sink));
  }
  ~LogCapture() { spdlog::set_default_logger(old_); }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> old_;
};

/// demo_schema() plus renamed keys: a top-level key, a key moved to another table, a key of the
/// table-array element and a key of one style.
Schema alias_schema() {
  Schema s = demo_schema();
  s.add_real("output.interval", 0.0, "s", 0.0, 1e9, "time between outputs");
  s.add_alias("output.every_s", "output.interval");
  s.add_alias("run.courant", "courant");
  Schema& body = *s.find_array("body")->element;
  body.add_alias("speed", "velocity");
  return s;
}

const char* kBodies = "[[body]]\nradius = 1\n";

std::string alias_error(const std::string& text, const std::vector<std::string>& sets = {}) {
  try {
    Scene::parse(alias_schema(), text, "scene.toml", sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneAlias, OldKeyInFileIsReadAsTheNewOneWithAWarning) {
  LogCapture log;
  const Scene s = Scene::parse(alias_schema(), std::string("[run]\ncourant = 0.25\n[output]\nevery_s = 3.5\n") + kBodies,
                               "scene.toml");
  EXPECT_DOUBLE_EQ(s.real("courant"), 0.25);
  EXPECT_DOUBLE_EQ(s.real("output.interval"), 3.5);
  EXPECT_TRUE(s.given("courant"));
  EXPECT_TRUE(s.given("output.interval"));
  const std::string w = log.text();
  EXPECT_NE(w.find("scene.toml: 'run.courant' is deprecated, use 'courant'"), std::string::npos) << w;
  EXPECT_NE(w.find("scene.toml: 'output.every_s' is deprecated, use 'output.interval'"), std::string::npos) << w;
  EXPECT_NE(w.find("[warning]"), std::string::npos) << w;
  // The resolved scene holds only the new names (its `run` table, left empty, is gone) and reads
  // back without warnings.
  const std::string echo = s.to_toml();
  EXPECT_EQ(echo.find("every_s"), std::string::npos) << echo;
  EXPECT_EQ(echo.find("[run]"), std::string::npos) << echo;
  LogCapture again;
  EXPECT_EQ(Scene::parse(alias_schema(), echo, "echo").to_toml(), echo);
  EXPECT_EQ(again.text(), "");
}

TEST(SceneAlias, OldKeyBySetIsReadAsTheNewOneAndWinsOverTheFile) {
  LogCapture log;
  const Scene s = Scene::parse(alias_schema(), std::string("courant = 0.3\n") + kBodies, "scene.toml",
                               {"run.courant=0.125", "body[0].speed=[1,2,3]"});
  EXPECT_DOUBLE_EQ(s.real("courant"), 0.125);
  EXPECT_DOUBLE_EQ(s.element("body", 0).vec3("velocity")[2], 3.0);
  EXPECT_NE(log.text().find("--set: 'run.courant' is deprecated, use 'courant'"), std::string::npos) << log.text();
  EXPECT_NE(log.text().find("--set: 'body[0].speed' is deprecated, use 'body[0].velocity'"), std::string::npos)
      << log.text();
  // And a --set of the new name wins over the old name in the file.
  const Scene t = Scene::parse(alias_schema(), std::string("[run]\ncourant = 0.3\n") + kBodies, "scene.toml",
                               {"courant=0.5"});
  EXPECT_DOUBLE_EQ(t.real("courant"), 0.5);
}

TEST(SceneAlias, AliasInsideTableArrayElements) {
  LogCapture log;
  const Scene s = Scene::parse(alias_schema(), "courant = 0.1\n[[body]]\nradius = 1\nspeed = [0, 0, -7]\n", "scene.toml");
  EXPECT_DOUBLE_EQ(s.element("body", 0).vec3("velocity")[2], -7.0);
  EXPECT_TRUE(s.element("body", 0).given("velocity"));
  EXPECT_NE(log.text().find("scene.toml: 'body[0].speed' is deprecated, use 'body[0].velocity'"), std::string::npos)
      << log.text();
}

TEST(SceneAlias, AliasOfAStyleKeyAndOfAnIncludedSchema) {
  Schema s("styles");
  s.add_choice("model", std::string("a"), {}, "model");
  Schema a;
  a.add_real("modulus", 1.0, "Pa", 0.0, 1e9, "modulus");
  a.add_alias("E", "modulus");
  s.add_style_switch("model", {{"a", a}, {"b", Schema()}});
  Schema outer;
  outer.include("mat", s);
  LogCapture log;
  const Scene sc = Scene::parse(outer, "[mat]\nE = 4.0\n", "scene.toml");
  EXPECT_DOUBLE_EQ(sc.real("mat.modulus"), 4.0);
  EXPECT_NE(log.text().find("'mat.E' is deprecated, use 'mat.modulus'"), std::string::npos) << log.text();
  // Under the other style the old name is as unknown as the new one.
  EXPECT_THROW(Scene::parse(outer, "[mat]\nmodel = \"b\"\nE = 4.0\n", "scene.toml"), InputError);
}

TEST(SceneAlias, OldAndNewTogetherIsAnErrorNamingBoth) {
  LogCapture log;
  for (const std::string& e :
       {alias_error(std::string("courant = 0.3\n[run]\ncourant = 0.25\n") + kBodies),
        alias_error(std::string("courant = 0.3\n") + kBodies, {"run.courant=0.2", "courant=0.1"}),
        alias_error("courant = 0.1\n[[body]]\nradius = 1\nspeed = [0, 0, 1]\nvelocity = [0, 0, 1]\n")}) {
    EXPECT_NE(e.find("deprecated"), std::string::npos) << e;
    const bool body = e.find("body[0].speed") != std::string::npos;
    EXPECT_NE(e.find(body ? "body[0].velocity" : "'courant'"), std::string::npos) << e;
    EXPECT_TRUE(body || e.find("run.courant") != std::string::npos) << e;
  }
  EXPECT_NE(alias_error(std::string("courant = 0.3\n[run]\ncourant = 0.25\n") + kBodies).find("scene.toml"),
            std::string::npos);
}

TEST(SceneAlias, DeclarationErrorsAndHelp) {
  Schema s = alias_schema();
  EXPECT_THROW(s.add_alias("x", "no.such.key"), std::logic_error);
  EXPECT_THROW(s.add_alias("courant", "time.end"), std::logic_error);       // old name still declared
  EXPECT_THROW(s.add_alias("run.courant", "time.end"), std::logic_error);   // alias declared twice
  EXPECT_THROW(s.add_real("run.courant", 1.0, "1", 0, 1, "reuse"), std::logic_error);
  const std::string h = s.help_text();
  EXPECT_NE(h.find("run.courant  DEPRECATED: use courant"), std::string::npos) << h;
  EXPECT_NE(h.find("body[i].speed  DEPRECATED: use body[i].velocity"), std::string::npos) << h;
}

// ---- typed choices (Choice tables) ----

namespace {
enum class Shape { ugimp, linear };
constexpr std::array kShapes{common::Choice{"ugimp", Shape::ugimp}, common::Choice{"linear", Shape::linear}};
enum class Unlisted { a, b };
constexpr std::array kUnlisted{common::Choice{"a", Unlisted::a}};
}  // namespace

TEST(SceneChoice, TypedChoiceComesFromOneTable) {
  static_assert(common::choice_name(kShapes, Shape::linear) == "linear");
  static_assert(*common::choice_value(kShapes, "ugimp") == Shape::ugimp);
  static_assert(!common::choice_value(kShapes, "gimp"));
  Schema s("typed");
  s.add_choice("shape", Shape::linear, kShapes, "shape functions");
  s.add_choice("req", std::nullopt, kShapes, "required");
  EXPECT_EQ(s.find("shape")->choices, (std::vector<std::string>{"ugimp", "linear"}));
  EXPECT_EQ(std::get<std::string>(*s.find("shape")->default_value), "linear");
  EXPECT_FALSE(s.find("req")->default_value);
  const Scene sc = Scene::parse(s, "req = \"ugimp\"\n", "scene.toml");
  EXPECT_EQ(sc.choice("shape", kShapes), Shape::linear);
  EXPECT_EQ(sc.choice("req", kShapes), Shape::ugimp);
  EXPECT_EQ(sc.string("req"), "ugimp");
  try {
    Scene::parse(s, "req = \"cubic\"\n", "scene.toml");
    ADD_FAILURE() << "accepted a value outside the table";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("\"ugimp\", \"linear\""), std::string::npos) << e.what();
  }
  EXPECT_NE(s.help_text().find("one of: ugimp linear"), std::string::npos);
  // Reading a key with a table it was not declared from is an internal error, not a silent default.
  Schema t;
  t.add_choice("k", std::string("b"), {"a", "b"}, "declared from strings");
  EXPECT_THROW(Scene::parse(t, "", "s").choice("k", kUnlisted), InputError);
  EXPECT_THROW(s.add_choice("bad", Unlisted::b, kUnlisted, "default not in the table"), std::logic_error);
}
