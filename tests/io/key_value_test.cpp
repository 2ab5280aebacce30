#include <gtest/gtest.h>

#include "config_refusal.h"
#include "io/key_value.h"

namespace quadfdi {
namespace {

std::string errorOf(const std::string& text) {
  return test::configRefusal([&] { parseKeyValue(text, "cfg.toml"); });
}

TEST(KeyValue, ParsesSectionsCommentsAndTypes) {
  const auto doc = parseKeyValue(
      "# vehicle\nmass = 0.03  # kg\n\n[train]\nname = \"a # b\"\nsteps = 100\nflag = true\nthetas = [0, 0.5, 1]\n",
      "cfg.toml");
  ASSERT_EQ(doc.entries.size(), 5u);
  EXPECT_EQ(doc.number(*doc.find("mass")), 0.03);
  EXPECT_EQ(doc.find("mass")->line, 2);
  EXPECT_EQ(doc.string(*doc.find("train.name")), "a # b");
  EXPECT_EQ(doc.integer(*doc.find("train.steps")), 100);
  EXPECT_TRUE(doc.boolean(*doc.find("train.flag")));
  EXPECT_EQ(doc.numberList(*doc.find("train.thetas")), (std::vector<double>{0, 0.5, 1}));
}

TEST(KeyValue, ErrorsNameFileAndLine) {
  EXPECT_EQ(errorOf("a = 1\nno equals here\n"), "cfg.toml:2: expected 'key = value', got 'no equals here'");
  EXPECT_EQ(errorOf("a = 1\na = 2\n"), "cfg.toml:2: duplicate key 'a'");
  EXPECT_EQ(errorOf("\n\n[bad\n"), "cfg.toml:3: section header needs a closing ']'");
  EXPECT_EQ(errorOf("k =\n"), "cfg.toml:1: key 'k' has no value");
  EXPECT_EQ(errorOf("s = \"open\n"), "cfg.toml:1: unterminated string in value of 's'");
  EXPECT_NE(errorOf(std::string("a = 1\nb\0c = 2\n", 13)).find("cfg.toml:2: binary data"), std::string::npos);
}

TEST(KeyValue, TypedAccessErrorsNameTheLine) {
  const auto doc = parseKeyValue("x = 1.5\ny = nan\nz = [1, two]\nw = 1e999\n", "c.toml");
  EXPECT_THROW(doc.integer(*doc.find("x")), ConfigError);
  try {
    doc.number(*doc.find("y"));
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "c.toml:2: 'y' needs a finite number, got 'nan'");
  }
  EXPECT_THROW(doc.numberList(*doc.find("z")), ConfigError);
  EXPECT_THROW(doc.number(*doc.find("w")), ConfigError);
}

TEST(KeyValue, StrictNumbers) {
  double v = 0;
  EXPECT_TRUE(parseFiniteNumber(" -1.25e-3 ", v));
  EXPECT_EQ(v, -1.25e-3);
  for (const char* bad : {"", "1.0x", "inf", "nan", "0x10", "1e400", "--1", "1,5"})
    EXPECT_FALSE(parseFiniteNumber(bad, v)) << bad;
}

TEST(KeyValue, MissingFileIsAOneLineError) {
  try {
    readKeyValueFile("/nonexistent/dir/x.toml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/dir/x.toml: cannot open for reading (No such file or directory)");
  }
}

}  // namespace
}  // namespace quadfdi
