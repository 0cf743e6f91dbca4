// Diagnostics name the file, line and column, show the source line with a caret, and recover
// to report several errors per file.
#include <gtest/gtest.h>

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
