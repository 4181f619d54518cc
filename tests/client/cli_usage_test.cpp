// Each program's command line: --help succeeds and bad usage prints the help and exits 2.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace {

struct ProgramRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string slurp(const std::string& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs `binary args` with stdout and stderr captured to files (no DDS traffic: every case here
// fails or finishes before a participant is created, except where noted).
ProgramRun run(const std::string& binary, const std::string& args) {
  const std::string base = ::testing::TempDir() + "cli_usage_" + std::to_string(::getpid());
  const std::string command = binary + " " + args + " > " + base + ".out 2> " + base + ".err < /dev/null";
  const int status = std::system(command.c_str());
  ProgramRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  return r;
}

void expectUsageError(const std::string& binary, const std::string& args, const std::string& help_mentions) {
  const ProgramRun r = run(binary, args);
  EXPECT_EQ(r.exit_code, 2) << binary << " " << args << "\n" << r.err;
  EXPECT_NE(r.err.find("Usage:"), std::string::npos) << "no help on stderr for: " << args << "\n" << r.err;
  EXPECT_NE(r.err.find(help_mentions), std::string::npos) << r.err;
}

void expectHelp(const std::string& binary, const std::string& mentions) {
  const ProgramRun r = run(binary, "--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Usage:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(mentions), std::string::npos) << r.out;
}

TEST(CliUsage, CameraHelpAndBadUsage) {
  expectHelp(SEMFUSE_CAMERA_BIN, "--depth-encoding");
  expectHelp(SEMFUSE_CAMERA_BIN, "=rvl");                                          // the default depth encoding
  expectUsageError(SEMFUSE_CAMERA_BIN, "", "--source");                            // required option missing
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source synthetic --bogus", "--source");  // unknown option
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source synthetic --depth-encoding jpeg", "--depth-encoding");
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source synthetic --rate -3", "--rate");
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source synthetic --stride 0", "--stride");
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source kinect", "--source");
  expectUsageError(SEMFUSE_CAMERA_BIN, "--source 7scenes:", "--source");
}

TEST(CliUsage, SegmenterHelpAndBadUsage) {
  expectHelp(SEMFUSE_SEGMENTER_BIN, "--noise-model");
  expectUsageError(SEMFUSE_SEGMENTER_BIN, "--backend magic", "--backend");
  expectUsageError(SEMFUSE_SEGMENTER_BIN, "--noise 1.5", "--noise");
  expectUsageError(SEMFUSE_SEGMENTER_BIN, "--every 0", "--every");
  expectUsageError(SEMFUSE_SEGMENTER_BIN, "--layout nwch", "--layout");
  expectUsageError(SEMFUSE_SEGMENTER_BIN, "stray-argument", "--backend");
}

TEST(CliUsage, ExampleSegmenterHelpAndBadUsage) {
  expectHelp(SEMFUSE_EXAMPLE_SEGMENTER_BIN, "--domain-id");
  // Plain CLI11 (the example depends on nothing but the client library): a non-zero exit code.
  const ProgramRun r = run(SEMFUSE_EXAMPLE_SEGMENTER_BIN, "--domain-id many");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--domain-id"), std::string::npos) << r.err;
}

TEST(CliUsage, QueryHelpAndBadUsage) {
  expectHelp(SEMFUSE_QUERY_BIN, "raycast");
  expectUsageError(SEMFUSE_QUERY_BIN, "", "Subcommands:");           // a subcommand is required
  expectUsageError(SEMFUSE_QUERY_BIN, "teleport", "Subcommands:");   // unknown subcommand
  expectUsageError(SEMFUSE_QUERY_BIN, "raycast --out x", "--pose");  // the subcommand's help
  expectUsageError(SEMFUSE_QUERY_BIN, "region --min 0 0 0", "--max");
  expectUsageError(SEMFUSE_QUERY_BIN, "mesh", "--out");
  expectUsageError(SEMFUSE_QUERY_BIN, "--timeout 0 status", "--timeout");
}

TEST(CliUsage, CameraOnAFolderThatIsNoDatasetFailsWithCode1) {
  const ProgramRun r = run(SEMFUSE_CAMERA_BIN, "--source 7scenes:/nonexistent/folder --wait-server 0");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/folder"), std::string::npos) << r.err;
}

TEST(CliUsage, QueryObjectsOfALabelNameTheLegendDoesNotHaveIsAUsageError) {
  // No server on this domain: the label is looked up in the fallback legend, before any call.
  const ProgramRun r = run(SEMFUSE_QUERY_BIN, "--domain-id 232 --timeout 0.3 --legend synthetic objects --label sofa");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("no label named 'sofa' in the legend 'synthetic'"), std::string::npos) << r.err;
  expectUsageError(SEMFUSE_QUERY_BIN, "objects --near 1 2", "--near");
  expectUsageError(SEMFUSE_QUERY_BIN, "objects --near 1 2 3 --radius -1", "--radius");
}

TEST(CliUsage, QueryWithoutServerTimesOutWithCode4) {
  // A domain nobody uses: no server can answer.
  const ProgramRun r = run(SEMFUSE_QUERY_BIN, "--domain-id 231 --timeout 0.3 objects");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(r.err.find("no server"), std::string::npos) << r.err;
}

}  // namespace
