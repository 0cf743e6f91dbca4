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

// A lambda applied to itself asks for the instance it is being checked in: E0307, as named
// recursion is (it crashed the checker: an unfinished function was used).
TEST(Robustness, SelfAppliedLambdasAreRecursionNotACrash) {
  for (const char* text : {"fn main() = (|f| f(f))(|f| f(f))\n",
                           "fn app(f, x) = f(f, x)\nfn main() = app(|g, y| g(g, y), 1.0)\n",
                           "fn b(f) = f(f) + 1\nfn main() = b(|g| g(g) + 1)\n"}) {
    Session s;
    s.loadSource("omega.tex", text);
    EXPECT_TRUE(has(codes(s), "E0307")) << text;
  }
}

// A type alias through function types refers to itself: E0310 at once (it expanded both the
// parameter and the result 64 levels deep, 2^64 steps).
TEST(Robustness, SelfReferentialFunctionAliasesAreReportedAtOnce) {
  for (const char* text : {"type S = (S) -> S\n", "type S = (S, S) -> Int\n", "type S = (Int) -> (S) -> S\n",
                           "type A = (B) -> B\ntype B = (A) -> A\n"}) {
    const auto start = std::chrono::steady_clock::now();
    Session s;
    s.loadSource("alias.tex", text);
    EXPECT_TRUE(has(codes(s), "E0310")) << text;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2)) << text;
  }
}

// Chains nested in chains: each is within the grammar's limits (256 levels, 4096 operators),
// but the tree is 250 x 4000 deep, which overflowed the interpreter and the compiler. The
// whole tree is bounded (8192 levels), and a tree just within it checks.
TEST(Robustness, NestedOperatorChainsAreBoundedAsAWhole) {
  std::string chain;
  for (int i = 0; i < 4000; ++i) chain += " + 1.0";
  std::string deep = "1.0";
  for (int level = 0; level < 250; ++level) deep = "(" + deep + ")" + chain;
  Session a;
  a.loadSource("deep.tex", "fn main() = " + deep + "\n");
  EXPECT_TRUE(has(codes(a), "E0202"));
  Session b;
  b.loadSource("ok.tex", "fn main() = ((1.0" + chain + ")" + chain + ")\n");  // 8002 levels
  EXPECT_FALSE(b.diags().hasErrors());
}

// Calls stack their callees' bodies: 60 functions of 4000-operator chains calling each other
// nest 240,000 levels. Asking for such an entry is E0413 before anything evaluates or compiles
// it; 15 of them (60,000 levels) are fine.
TEST(Robustness, CallChainsOfLongBodiesAreBoundedWhenInstantiated) {
  auto program = [](int functions) {
    std::string chain;
    for (int i = 0; i < 4000; ++i) chain += " + 1.0";
    std::string text = "fn g0(x: Float) -> Float = x" + chain + "\n";
    for (int i = 1; i < functions; ++i)
      text += "fn g" + std::to_string(i) + "(x: Float) -> Float = g" + std::to_string(i - 1) + "(x)" + chain + "\n";
    return text + "fn main(x: Float) -> Float = g" + std::to_string(functions - 1) + "(x)\n";
  };
  const Type* f = TypeTable::global().floating();
  Session a;
  ModuleInfo* ma = a.loadSource("long.tex", program(60));
  ASSERT_FALSE(a.diags().hasErrors());
  EXPECT_LT(a.instantiate(ma, "main", {f}, Span{}), 0);
  EXPECT_TRUE(has(codes(a), "E0413"));
  Session b;
  ModuleInfo* mb = b.loadSource("ok.tex", program(15));
  EXPECT_GE(b.instantiate(mb, "main", {f}, Span{}), 0);
  EXPECT_FALSE(b.diags().hasErrors());
}
