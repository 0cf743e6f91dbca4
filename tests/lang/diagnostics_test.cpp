// Diagnostics name the file, line and column, show the source line with a caret, and recover
// to report several errors per file.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "lang/session.h"

using namespace tex::lang;

TEST(Diagnostics, RenderedWithFileLineColumnAndCaret) {
  Session s;
  s.loadSource("bad.tex", "let x = (1 +\n");
  ASSERT_EQ(s.diags().size(), 1u);
  std::string text = renderDiagnostic(s.diags().items()[0]);
  EXPECT_NE(text.find("bad.tex:1:9: error[E0203]: unclosed '('"), std::string::npos) << text;
  EXPECT_NE(text.find(" 1 | let x = (1 +\n   |         ^\n"), std::string::npos) << text;
}

TEST(Diagnostics, ParserRecoversAndReportsEveryBadItem) {
  Session s;
  s.loadSource("two.tex", "fn a() = 1 +\nfn b() = )\nfn c() = 3\n");
  ASSERT_EQ(s.diags().size(), 2u);
  EXPECT_EQ(s.diags().items()[0].span.file->lineCol(s.diags().items()[0].span.begin).line, 2u);
}

TEST(Diagnostics, UnknownNameSuggestsTheClosestName) {
  Session s;
  s.loadSource("typo.tex", "fn stripes(x: Float) -> Float = x\nfn main() = stripse(1.0)\n");
  ASSERT_EQ(s.diags().size(), 1u);
  EXPECT_EQ(s.diags().items()[0].code, "E0301");
  EXPECT_NE(s.diags().items()[0].help.find("stripes"), std::string::npos);
}

TEST(Diagnostics, ColumnsCountCodePoints) {
  Session s;
  s.loadSource("utf8.tex", "/* héllo wörld */ fn main() = x\n");
  ASSERT_EQ(s.diags().size(), 1u);
  auto lc = s.diags().items()[0].span.file->lineCol(s.diags().items()[0].span.begin);
  EXPECT_EQ(lc.col, 31u);
}

TEST(Diagnostics, ErrorsInsideGenericInstancesAreReportedOnce) {
  Session s;
  s.loadSource("gen.tex", "fn f(x) = x && true\nfn main() = f(1) && f(2)\n");
  int e0402 = 0;
  for (auto& d : s.diags().items()) e0402 += d.code == "E0402";
  EXPECT_EQ(e0402, 1);
}

// The REPL undoes a request that fails (Session::replMark / replRollback): the names it tried
// to define stay unknown, a module it failed to load is read afresh next time, and a retry
// reports the same errors again (diagnostics are deduplicated within one request only).
static int countCode(const Diagnostics& diags, const std::string& code) {
  int n = 0;
  for (const Diagnostic& d : diags.items()) n += d.code == code;
  return n;
}

TEST(Diagnostics, FailedReplDefinitionLeavesNoTraceAndIsReportedAgain) {
  Session s;
  Expr* expr = nullptr;
  ASSERT_TRUE(s.addReplInput("fn f() -> Int = 1", expr, 1));
  for (int attempt = 0; attempt < 2; ++attempt) {
    Session::ReplMark mark = s.replMark();
    EXPECT_FALSE(s.addReplInput("fn f() -> Int = 1 + true", expr, 2 + attempt));
    EXPECT_EQ(countCode(s.diags(), "E0402"), 1) << "attempt " << attempt;
    s.replRollback(mark);
    s.diags().clear();
    // The earlier, good f is back in scope.
    const FunctionDecl* f = s.findFunction(s.replModule(), "f");
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->item->name, "f");
    ASSERT_TRUE(s.addReplInput("f()", expr, 10 + attempt));
    EXPECT_GE(s.compileExpression(s.replModule(), expr, {}), 0);
    EXPECT_EQ(s.diags().size(), 0u);
  }
  Session::ReplMark mark = s.replMark();
  EXPECT_FALSE(s.addReplInput("let x = nosuch", expr, 20));
  s.replRollback(mark);
  s.diags().clear();
  EXPECT_EQ(s.findFunction(s.replModule(), "x"), nullptr);
}

TEST(Diagnostics, ReplReportsAGenericErrorAtEveryUse) {
  Session s;
  Expr* expr = nullptr;
  ASSERT_TRUE(s.addReplInput("fn g(x) = x + true", expr, 1));
  for (int n = 2; n < 5; ++n) {
    Session::ReplMark mark = s.replMark();
    ASSERT_TRUE(s.addReplInput("g(1)", expr, n));
    ASSERT_NE(expr, nullptr);
    EXPECT_LT(s.compileExpression(s.replModule(), expr, {}), 0);
    EXPECT_EQ(countCode(s.diags(), "E0402"), 1) << "use " << n;
    s.replRollback(mark);
    s.diags().clear();
  }
}

TEST(Diagnostics, ReplRollbackForgetsAModuleThatFailedToLoad) {
  std::string path = testing::TempDir() + "repl_rollback_part.tex";
  FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("fn good() = 1\nfn bad() = 1 + true\n", f);
  std::fclose(f);
  Session s;
  for (int attempt = 0; attempt < 2; ++attempt) {
    Session::ReplMark mark = s.replMark();
    ModuleInfo* m = s.loadFile(path);
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(countCode(s.diags(), "E0402"), 1) << "attempt " << attempt;
    s.replRollback(mark);
    s.diags().clear();
  }
  std::remove(path.c_str());
}
