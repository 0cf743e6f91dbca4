// The interpreter on whole programs: stdlib textures evaluate, and the session is re-entrant
// across threads (tex eval evaluates pixels in parallel on one program).
#include <gtest/gtest.h>

#include <thread>

#include "lang/interpreter.h"
#include "lang/session.h"

using namespace tex::lang;

TEST(Interpreter, HigherOrderFunctionsAreSpecialisedWithoutIndirectCalls) {
  Session s;
  ModuleInfo* m = s.loadSource("hof.tex",
                               "fn twice(f, x) = f(f(x))\n"
                               "fn main() = twice(|v| v * 3.0, 2.0) + float(twice(|v| v + 1, 1))\n");
  ASSERT_FALSE(s.diags().hasErrors());
  int fn = s.instantiate(m, "main", {}, Span{});
  ASSERT_GE(fn, 0);
  EXPECT_EQ(evaluate(s.program(), fn, {}).f[0], 21.0f);
  // Two lambdas of different types give two instances of twice.
  int twiceInstances = 0;
  for (auto& f : s.program().functions) twiceInstances += f.name.rfind("hof.twice<", 0) == 0;
  EXPECT_EQ(twiceInstances, 2);
}

TEST(Interpreter, ConcurrentEvaluationAgreesWithSerial) {
  Session s;
  ModuleInfo* m = s.loadSource("par.tex",
                               "export fn tex(h: Hit) -> Float = fold(50, 0.0, |a, i| a + sin(h.uv.x * float(i)))\n");
  ASSERT_FALSE(s.diags().hasErrors());
  int fn = s.instantiate(m, "tex", {TypeTable::global().hit()}, Span{});
  ASSERT_GE(fn, 0);
  std::vector<float> serial(64), parallel(64);
  for (int i = 0; i < 64; ++i) serial[i] = evaluate(s.program(), fn, {makeHit(i / 64.0f, 0.5f)}).f[0];
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int i = t; i < 64; i += 4) parallel[i] = evaluate(s.program(), fn, {makeHit(i / 64.0f, 0.5f)}).f[0];
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
}

TEST(Interpreter, StdlibModulesCheckCleanly) {
  for (const char* name : {"math", "noise", "patterns", "color", "spectra", "materials"}) {
    Session s;
    s.loadFile(std::string(TEX_SOURCE_DIR) + "/stdlib/std/" + name + ".tex");
    for (auto& d : s.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  }
}

TEST(Interpreter, LongReplSessionNeverHitsTheSpecialisationLimit) {
  // The E0413 limit bounds one request, not the lifetime of a session.
  Session s;
  Expr* expr = nullptr;
  for (int n = 0; n < 25000; ++n) {
    ASSERT_TRUE(s.addReplInput("(|x| x + " + std::to_string(n) + ")(1)", expr, n));
    ASSERT_GE(s.compileExpression(s.replModule(), expr, {}), 0) << "line " << n;
  }
}

TEST(Interpreter, ReplRollbackKeepsALongSessionFromGrowing) {
  // The REPL compiles each expression, evaluates it and rolls the IR back (cli/cmd_repl.cpp).
  Session s;
  Expr* expr = nullptr;
  ASSERT_TRUE(s.addReplInput("fn twice(f, x) = f(f(x))", expr, 0));
  Session::Mark start = s.mark();
  for (int n = 1; n <= 2000; ++n) {
    ASSERT_TRUE(s.addReplInput("twice(|v| v * " + std::to_string(n) + ".0, 1.5)", expr, n));
    Session::Mark before = s.mark();
    int fn = s.compileExpression(s.replModule(), expr, {});
    ASSERT_GE(fn, 0);
    EXPECT_EQ(evaluate(s.program(), fn, {}).f[0], 1.5f * float(n) * float(n));
    s.rollback(before);
  }
  EXPECT_EQ(s.mark().functions, start.functions);
  EXPECT_EQ(s.mark().nodes, start.nodes);
}
