// quadfdi evaluate on a tiny scale: the report generator writes every file, and names what
// it could not run.
#include <gtest/gtest.h>

#include "cli/cli_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace {

std::string run(const std::string& args, int* code) {
  const quadfdi::test::CommandResult r = quadfdi::test::runQuadfdi(args);
  *code = r.exit_code;
  return r.out;
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(EvaluateCli, TinyReportWithTablesFiguresAndSkippedExperiments) {
  const std::string dir = ::testing::TempDir() + "quadfdi_eval_cli";
  const std::string model = dir + ".qfdi";
  int code = 0;
  const std::string trained =
      run("train --scale tiny --max-iterations 1 --max-minibatches 1 --batch-size 32 -q -o " + model, &code);
  ASSERT_EQ(code, 0) << trained;
  const std::string out = run("evaluate --model " + model + " -e e1 e4 --scale tiny -q -o " + dir, &code);
  ASSERT_EQ(code, 0) << out;
  const std::string report = slurp(dir + "/REPORT.md");
  EXPECT_NE(report.find("scale: tiny (3 test flights per class"), std::string::npos) << report;
  EXPECT_NE(report.find("### E1: complete failure of each motor"), std::string::npos);
  EXPECT_NE(report.find("| motor 4 | 3 |"), std::string::npos) << report;
  EXPECT_NE(report.find("### e4: not run — needs the model-based model"), std::string::npos);
  const std::string csv = slurp(dir + "/e1.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "faulty_length,faulty_time_ms,\"isolation: motor 1\",\"isolation: motor 2\",\"isolation: motor 3\","
            "\"isolation: motor 4\",\"identification: motor 1\",\"identification: motor 2\",\"identification: motor 3\","
            "\"identification: motor 4\"");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 102);  // header + L = 0 … 100
  EXPECT_NE(slurp(dir + "/e1.md").find("| condition | flights |"), std::string::npos);
  // Bad input: one line, non-zero.
  const std::string bad = run("evaluate --model " + model + " -e e9 --scale tiny -o " + dir, &code);
  EXPECT_NE(code, 0);
  EXPECT_EQ(bad, "quadfdi: error: --experiments: 'e9' is not one of: e1, e2, e3, e4, e5, e6, e7, decisions\n");
  run("evaluate --model /nonexistent.qfdi -o " + dir, &code);
  EXPECT_NE(code, 0);
}

}  // namespace
