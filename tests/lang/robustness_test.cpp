// Hostile and pathological input gets diagnostics, never a crash, hang or stack overflow.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include "lang/session.h"

using namespace tex::lang;

namespace {

std::vector<std::string> codes(Session& s) {
  std::vector<std::string> out;
  for (auto& d : s.diags().items()) out.push_back(d.code);
  return out;
}

bool has(const std::vector<std::string>& v, const std::string& code) {
  return std::find(v.begin(), v.end(), code) != v.end();
}

}  // namespace

TEST(Robustness, HundredThousandOpenParensIsNestingError) {
  Session s;
  s.loadSource("deep.tex", "fn main() = " + std::string(100000, '('));
  EXPECT_TRUE(has(codes(s), "E0202"));
}

TEST(Robustness, HundredThousandBalancedParensIsNestingError) {
  Session s;
  s.loadSource("deep.tex", "fn main() = " + std::string(100000, '(') + "1" + std::string(100000, ')'));
  EXPECT_TRUE(has(codes(s), "E0202"));
}

TEST(Robustness, LongOperatorChainIsBoundedNotOverflowing) {
  std::string ok = "fn main() = 1";
  for (int i = 0; i < 4000; ++i) ok += " + 1";
  Session a;
  a.loadSource("chain.tex", ok);
  EXPECT_FALSE(a.diags().hasErrors());
  std::string tooLong = "fn main() = 1";
  for (int i = 0; i < 200000; ++i) tooLong += "+1";
  Session b;
  b.loadSource("chain.tex", tooLong);
  EXPECT_TRUE(has(codes(b), "E0202"));
}

TEST(Robustness, InvalidUtf8AndNulAreReported) {
  Session s;
  s.loadSource("utf.tex", std::string("\xff\xfe\x00 let \xc3\x28", 9));
  auto c = codes(s);
  EXPECT_TRUE(has(c, "E0101"));
  EXPECT_TRUE(has(c, "E0102"));
}

TEST(Robustness, TenMegabyteModuleChecksInBoundedTime) {
  std::string text;
  for (int i = 0; text.size() < (size_t(10) << 20); ++i)
    text += "fn f" + std::to_string(i) + "(x: Float) -> Float = x * 2.0 + " + std::to_string(i) + ".0\n";
  auto start = std::chrono::steady_clock::now();
  Session s;
  s.loadSource("big.tex", text);
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_FALSE(s.diags().hasErrors());
  EXPECT_LT(seconds, 60.0);  // a hang guard, not a benchmark (bench/bench_lang.cpp measures)
}

TEST(Robustness, SelfImportIsACycle) {
  auto dir = std::filesystem::temp_directory_path() / "tex_self_import";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "me.tex") << "import me.{f}\nexport fn f(x: Float) -> Float = x\n";
  Session s;
  s.loadFile((dir / "me.tex").string());
  EXPECT_TRUE(has(codes(s), "E0304"));
}

TEST(Robustness, MissingFileIsAnErrorNotACrash) {
  Session s;
  EXPECT_EQ(s.loadFile("/nonexistent/dir/none.tex"), nullptr);
  EXPECT_TRUE(s.diags().hasErrors());
}

TEST(Robustness, InstanceExplosionHitsTheSpecialisationLimit) {
  // Each level doubles the record type; instances stay linear but types grow: must stay bounded.
  std::string text = "fn g0(x) = {a: x, b: x}\n";
  for (int i = 1; i < 40; ++i)
    text += "fn g" + std::to_string(i) + "(x) = g" + std::to_string(i - 1) + "({a: x, b: x})\n";
  text += "fn main() = g39(1).a\n";
  Session s;
  s.loadSource("explode.tex", text);
  SUCCEED();  // reaching here without a crash or hang is the property
}
