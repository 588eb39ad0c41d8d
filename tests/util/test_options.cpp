// The options table's pieces (util/options.h): typed binding, bounds,
// config files.
#include <gtest/gtest.h>

#include <cmath>

#include "fluidtex/util/options.h"
#include "test_util.h"

namespace fluidtex {
namespace {

enum class Shade { Light, Dark };
inline constexpr EnumName<Shade> kShadeNames[] = {{Shade::Light, "light"}, {Shade::Dark, "dark"}};
constexpr const auto& enum_names(Shade) { return kShadeNames; }

struct Sample {
  double ratio = 0.5;
  int count = 3;
  std::uint64_t seed = 1;
  bool loud = false;
  std::string path;
  std::vector<std::string> layers;
  std::optional<double> length;
  Shade shade = Shade::Light;

  template <class Self, class F>
  static void for_each_option(Self& o, F&& f) {
    f(OptionInfo{.name = "ratio", .help = "r", .bounds = between(0, 1, false, true)}, o.ratio);
    f(OptionInfo{.name = "count", .help = "c", .bounds = at_least(1)}, o.count);
    f(OptionInfo{.name = "seed", .help = "s"}, o.seed);
    f(OptionInfo{.name = "loud", .help = "l", .group = "Console"}, o.loud);
    f(OptionInfo{.name = "path", .help = "p"}, o.path);
    f(OptionInfo{.name = "layers", .help = "ls", .choices = "a, b"}, o.layers);
    f(OptionInfo{.name = "length", .help = "len", .bounds = above(0)}, o.length);
    f(OptionInfo{.name = "shade", .help = "sh"}, o.shade);
  }
};

std::vector<OptionRef> table(Sample& s) {
  std::vector<OptionRef> t;
  Sample::for_each_option(s, [&](const OptionInfo& info, auto& field) { t.push_back(bind_option(info, field)); });
  return t;
}

TEST(OptionTable, BoundsDescribeAndCheck) {
  EXPECT_EQ(between(-1, 1, false, true).describe(), "must be in [-1, 1)");
  EXPECT_EQ(above(0).describe(), "must be > 0");
  EXPECT_EQ(at_least(2).describe(), "must be >= 2");
  EXPECT_FALSE(above(0).contains(0.0));
  EXPECT_FALSE(at_least(0).contains(std::nan("")));
  Sample s;
  EXPECT_NO_THROW(check_options(s));
  s.ratio = 1.0;
  EXPECT_THROW(check_options(s), InputError);
  s = Sample{};
  s.layers = {"a", "c"};
  try {
    check_options(s);
    FAIL() << "unknown list value accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--layers: unknown value 'c' (use a, b)");
  }
  s = Sample{};
  s.length = 0.0;
  EXPECT_THROW(check_options(s), InputError);
  s.length.reset();  // automatic
  EXPECT_NO_THROW(check_options(s));
}

TEST(OptionTable, EveryTypeParsesWhatItPrints) {
  Sample s;
  std::vector<OptionRef> t = table(s);
  const std::vector<std::vector<std::string>> values = {
      {"0.25"}, {"7"}, {"18446744073709551615"}, {"true"}, {"a b"}, {"a", "b,a"}, {"1.5"}, {"dark"}};
  for (std::size_t k = 0; k < t.size(); ++k) t[k].set(values[k]);
  EXPECT_EQ(s.ratio, 0.25);
  EXPECT_EQ(s.count, 7);
  EXPECT_EQ(s.seed, 18446744073709551615ull);
  EXPECT_TRUE(s.loud);
  EXPECT_EQ(s.path, "a b");
  EXPECT_EQ(s.layers, (std::vector<std::string>{"a", "b", "a"}));
  EXPECT_EQ(s.length, 1.5);
  EXPECT_EQ(s.shade, Shade::Dark);
  Sample copy;
  std::vector<OptionRef> u = table(copy);
  for (std::size_t k = 0; k < t.size(); ++k)
    u[k].set(t[k].kind == OptionRef::Kind::List ? s.layers : std::vector<std::string>{t[k].text()});
  EXPECT_EQ(format_toml(u), format_toml(t));
  t[6].set({"auto"});
  EXPECT_FALSE(s.length.has_value());
  EXPECT_EQ(t[6].toml(), "\"auto\"");
}

TEST(OptionTable, ATextOptionWithChoicesRefusesTheOthers) {
  std::string format = "ply";
  const OptionRef ref = bind_option(OptionInfo{.name = "format", .help = "f", .choices = "ply, vdb"}, format);
  EXPECT_EQ(ref.choices, (std::vector<std::string>{"ply", "vdb"}));
  EXPECT_NO_THROW(ref.check());
  ref.set({"obj"});
  try {
    ref.check();
    FAIL() << "unknown text value accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--format: unknown value 'obj' (use ply, vdb)");
  }
}

TEST(OptionTable, BadTextIsAnInputErrorNamingTheOption) {
  Sample s;
  std::vector<OptionRef> t = table(s);
  auto message = [&](std::size_t k, const std::string& v) {
    try {
      t[k].set({v});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message(0, "1.5x"), "--ratio: expected a number, got '1.5x'");
  EXPECT_EQ(message(1, "2.5"), "--count: expected an integer in [-2147483648, 2147483647], got '2.5'");
  EXPECT_EQ(message(2, "-1"), "--seed: expected an integer in [0, 18446744073709551615], got '-1'");
  EXPECT_EQ(message(3, "maybe"), "--loud: expected true or false, got 'maybe'");
  EXPECT_EQ(message(7, "grey"), "--shade must be light or dark (got 'grey')");
}

TEST(OptionTable, ConfigFileRoundTripAndErrorsNameTheFile) {
  test::TempDir dir;
  Sample s;
  s.ratio = 0.125, s.path = "mesh.####.ply", s.layers = {"b"}, s.length = 2.0, s.shade = Shade::Dark, s.loud = true;
  const std::string text = format_toml(table(s));
  EXPECT_NE(text.find("\n# Console\n"), std::string::npos) << text;
  test::write_file(dir.path() / "c.toml", text);
  Sample back;
  apply_config(read_config_file(dir.file("c.toml")), table(back), dir.file("c.toml"),
               [](const std::string&) { return false; });
  EXPECT_EQ(format_toml(table(back)), text);  // '#' inside quotes is not a comment

  // Skipped names keep their value (the command line's).
  Sample kept;
  kept.ratio = 0.75;
  apply_config(read_config_file(dir.file("c.toml")), table(kept), "c.toml",
               [](const std::string& name) { return name == "ratio"; });
  EXPECT_EQ(kept.ratio, 0.75);
  EXPECT_EQ(kept.path, "mesh.####.ply");

  test::write_file(dir.path() / "bad.toml", "ratio = 2\n");
  try {
    Sample t;
    apply_config(read_config_file(dir.file("bad.toml")), table(t), "bad.toml",
                 [](const std::string&) { return false; });
    FAIL() << "out-of-range value accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "bad.toml: --ratio must be in [0, 1) (got 2)");
  }
  test::write_file(dir.path() / "unknown.toml", "colour = 2\n");
  Sample u;
  EXPECT_THROW(
      apply_config(read_config_file(dir.file("unknown.toml")), table(u), "u", [](const std::string&) { return false; }),
      InputError);
  EXPECT_THROW(read_config_file(dir.file("missing.toml")), InputError);
}

}  // namespace
}  // namespace fluidtex
