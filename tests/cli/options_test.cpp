// The declarative option table (cli/options.h) in-process: one declaration fills a field from a
// flag or from a config key, the command line wins over the file, unknown keys and bad values
// are refused with one line naming the flag or FILE:LINE, and --help shows help and default.
#include "cli/options.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "io/key_value.h"
#include "scratch_path.h"

namespace quadfdi::cli {
namespace {

struct DemoOptions {
  std::string config;
  std::string controller = "lqr";
  int steps = 1000;
  double theta = 0.0;
  unsigned long long seed = 1;
  std::vector<double> thetas{0.0, 1.0};
  std::vector<double> goal;
  std::optional<int> batch_size;
  std::string output;
  bool quiet = false;
  std::set<std::string> given;
};

// A command "demo" with a table over `o`; `required_output` makes --output required.
struct Demo {
  CLI::App app{"test"};
  CLI::App* cmd = nullptr;
  explicit Demo(DemoOptions& o, bool required_output = false) {
    cmd = app.add_subcommand("demo", "A demo command");
    auto t = std::make_shared<OptionTable>();
    t->addConfigFile(o.config);
    t->recordGivenIn(o.given);
    t->add("--controller", o.controller, "Controller").choices({"lqr", "cbf"});
    t->add("--steps", o.steps, "Control steps").range(1, 100000);
    t->add("--theta", o.theta, "Effectiveness").range(0.0, 1.0);
    t->add("--seed", o.seed, "Seed");
    t->add("--thetas", o.thetas, "Values").range(0.0, 1.0);
    t->add("--goal", o.goal, "Goal X Y Z").values(3);
    t->add("--batch-size", o.batch_size, "Minibatch").atLeast(1).defaultText("from the scale");
    Option& output = t->add("--output,-o", o.output, "Output file");
    if (required_output) output.required();
    t->add("--quiet,-q", o.quiet, "Quiet");
    attachOptions(*cmd, t);
  }
  // Parses `args` (after the program name); rethrows what the table throws.
  void parse(std::vector<std::string> args) {
    args.insert(args.begin(), "demo");
    std::reverse(args.begin(), args.end());  // CLI11 takes them last-first
    app.parse(args);
  }
};

std::string writeConfig(const std::string& name, const std::string& text) {
  const std::string path = quadfdi::test::scratchPath("options", name);
  std::ofstream(path) << text;
  return path;
}

// The message of what parsing `args` throws ("" when it does not throw).
std::string errorOf(const std::vector<std::string>& args, bool required_output = false) {
  DemoOptions o;
  Demo d(o, required_output);
  try {
    d.parse(args);
  } catch (const std::exception& e) {
    return e.what();
  }
  return {};
}

TEST(Options, AFlagAndAConfigKeyFillTheSameField) {
  DemoOptions from_flags;
  Demo(from_flags).parse({"--steps", "20", "--thetas", "0", "0.5", "--controller", "cbf", "-q", "--batch-size", "64",
                          "--seed", "18446744073709551615"});
  EXPECT_EQ(from_flags.steps, 20);
  EXPECT_EQ(from_flags.thetas, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(from_flags.controller, "cbf");
  EXPECT_TRUE(from_flags.quiet);
  EXPECT_EQ(from_flags.batch_size, 64);
  EXPECT_EQ(from_flags.seed, 18446744073709551615ull);  // exact, beyond a double's 2^53

  const std::string cfg = writeConfig("same.toml",
                                      "# comment\nsteps = 20\nthetas = [0, 0.5]\ncontroller = \"cbf\"\nquiet = true\n"
                                      "batch_size = 64\nseed = 1e3\n");
  DemoOptions from_file;
  Demo(from_file).parse({"--config", cfg});
  EXPECT_EQ(from_file.steps, 20);
  EXPECT_EQ(from_file.thetas, (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(from_file.controller, "cbf");
  EXPECT_TRUE(from_file.quiet);
  EXPECT_EQ(from_file.batch_size, 64);
  EXPECT_EQ(from_file.seed, 1000u);
  EXPECT_EQ(from_file.given, (std::set<std::string>{"steps", "thetas", "controller", "quiet", "batch_size", "seed"}));

  DemoOptions untouched;
  Demo(untouched).parse({});
  EXPECT_EQ(untouched.steps, 1000);  // the field's initial value is the default
  EXPECT_FALSE(untouched.batch_size.has_value());
  EXPECT_TRUE(untouched.given.empty());
}

TEST(Options, TheCommandLineWinsOverTheFile) {
  const std::string cfg = writeConfig("wins.toml", "steps = 20\ntheta = 0.25\noutput = \"file.out\"\n");
  DemoOptions o;
  Demo(o, true).parse({"--config", cfg, "--steps", "30", "-o", "cli.out"});
  EXPECT_EQ(o.steps, 30);
  EXPECT_EQ(o.output, "cli.out");
  EXPECT_DOUBLE_EQ(o.theta, 0.25);  // not on the command line: the file's
  // The order on the command line does not matter.
  DemoOptions p;
  Demo(p).parse({"--steps", "30", "--config", cfg});
  EXPECT_EQ(p.steps, 30);
  // A required option may come from the file.
  DemoOptions q;
  Demo(q, true).parse({"--config", cfg});
  EXPECT_EQ(q.output, "file.out");
}

TEST(Options, UnknownAndBadConfigKeysAreRefusedWithFileAndLine) {
  const std::string unknown = writeConfig("unknown.toml", "steps = 20\n\nbogus = 3\n");
  EXPECT_EQ(errorOf({"--config", unknown}), unknown + ":3: unknown key 'bogus'");
  const std::string bad_choice = writeConfig("choice.toml", "controller = \"pid\"\n");
  EXPECT_EQ(errorOf({"--config", bad_choice}), bad_choice + ":1: controller: 'pid' is not one of: lqr, cbf");
  const std::string bad_number = writeConfig("number.toml", "steps = ten\n");
  EXPECT_EQ(errorOf({"--config", bad_number}), bad_number + ":1: steps: needs an integer, got 'ten'");
  const std::string out_of_range = writeConfig("range.toml", "thetas = [0, 1.5]\n");
  EXPECT_EQ(errorOf({"--config", out_of_range}), out_of_range + ":1: thetas: must be in [0, 1], got 1.5");
  const std::string list_for_scalar = writeConfig("list.toml", "steps = [1, 2]\n");
  EXPECT_EQ(errorOf({"--config", list_for_scalar}), list_for_scalar + ":1: steps: needs a single value, got 2");
  const std::string wrong_count = writeConfig("count.toml", "goal = [1, 2]\n");
  EXPECT_EQ(errorOf({"--config", wrong_count}), wrong_count + ":1: goal: needs 3 values, got 2");
  // A bad value in the file is refused even where the command line overrides it.
  EXPECT_EQ(errorOf({"--config", bad_number, "--steps", "5"}), bad_number + ":1: steps: needs an integer, got 'ten'");
  // The file itself: missing, or not key = value.
  EXPECT_NE(errorOf({"--config", "/nonexistent.toml"}).find("/nonexistent.toml: cannot open"), std::string::npos);
  const std::string garbage = writeConfig("garbage.toml", "steps 20\n");
  EXPECT_EQ(errorOf({"--config", garbage}).rfind(garbage + ":1: ", 0), 0u);
  // The config key is the long flag without "--", '-' → '_': the flag's spelling is not a key.
  const std::string dashed = writeConfig("dashed.toml", "batch-size = 3\n");
  EXPECT_EQ(errorOf({"--config", dashed}), dashed + ":1: unknown key 'batch-size'");
}

TEST(Options, BadCommandLineValuesNameTheFlag) {
  EXPECT_EQ(errorOf({"--controller", "pid"}), "--controller: 'pid' is not one of: lqr, cbf");
  EXPECT_EQ(errorOf({"--steps", "0"}), "--steps: must be in [1, 100000], got 0");
  EXPECT_EQ(errorOf({"--steps", "ten"}), "--steps: needs an integer, got 'ten'");
  EXPECT_EQ(errorOf({"--steps", "2.5"}), "--steps: needs an integer, got '2.5'");
  EXPECT_EQ(errorOf({"--theta", "nan"}), "--theta: needs a finite number, got 'nan'");
  EXPECT_EQ(errorOf({"--thetas", "0.5", "-1"}), "--thetas: must be in [0, 1], got -1");
  EXPECT_EQ(errorOf({"--batch-size", "0"}), "--batch-size: must be >= 1, got 0");
  EXPECT_EQ(errorOf({"--seed", "-3"}), "--seed: needs an integer >= 0, got '-3'");
  EXPECT_EQ(errorOf({}, true), "--output: required (on the command line, or as 'output' in --config)");
  // What CLI11 itself refuses stays a usage error (main() exits 2 for those).
  DemoOptions o;
  Demo d(o);
  EXPECT_THROW(d.parse({"--bogus"}), CLI::ParseError);
  DemoOptions p;
  Demo e(p);
  EXPECT_THROW(e.parse({"--goal", "1", "2"}), CLI::ParseError);
  // A bad value is an OptionError (a std::runtime_error), not a CLI11 usage error.
  DemoOptions q;
  Demo f(q);
  EXPECT_THROW(f.parse({"--steps", "0"}), OptionError);
}

TEST(Options, HelpShowsEveryOptionWithItsDefault) {
  DemoOptions o;
  Demo d(o);
  const std::string help = d.cmd->help();
  for (const char* line : {"--controller lqr|cbf", "Controller (default: lqr)", "--steps INT", "Control steps (default: 1000)",
                           "--thetas NUMBER ...", "Values (default: 0 1)", "--goal NUMBER x 3",
                           "Minibatch (default: from the scale)", "-o,--output TEXT", "-q,--quiet", "--config"})
    EXPECT_NE(help.find(line), std::string::npos) << line << "\n" << help;
  EXPECT_EQ(help.find("Output file (default:"), std::string::npos) << help;  // empty defaults are not shown
  EXPECT_EQ(help.find("Quiet (default"), std::string::npos) << help;
}

TEST(Options, ValueParsers) {
  int i = 0;
  EXPECT_EQ(parseOptionValue("-12", i), "");
  EXPECT_EQ(i, -12);
  EXPECT_EQ(parseOptionValue("1e3", i), "");
  EXPECT_EQ(i, 1000);
  EXPECT_EQ(parseOptionValue("3000000000", i), "needs an integer, got '3000000000'");
  double d = 0;
  EXPECT_EQ(parseOptionValue("0x10", d), "needs a finite number, got '0x10'");
  EXPECT_EQ(parseOptionValue("-2.5e-3", d), "");
  EXPECT_DOUBLE_EQ(d, -2.5e-3);
  bool b = false;
  EXPECT_EQ(parseOptionValue("yes", b), "needs true or false, got 'yes'");
}

// firstGiven / refuseGiven: the first of the keys given, as its flag; nothing when none was.
TEST(Options, AGivenOptionAModeDoesNotReadIsNamedAsItsFlag) {
  const std::set<std::string> given{"max_thrust", "seed"};
  EXPECT_EQ(firstGiven(given, {"mass", "max_thrust", "seed"}), "--max-thrust");
  EXPECT_EQ(firstGiven(given, {"mass"}), "");
  EXPECT_NO_THROW(refuseGiven(given, {"mass", "ekf_core"}, "unused"));
  try {
    refuseGiven(given, {"ekf_core", "seed"}, "is not read here");
    ADD_FAILURE() << "no error";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(), "--seed: is not read here");
  }
}

}  // namespace
}  // namespace quadfdi::cli
