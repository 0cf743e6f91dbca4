// libFuzzer target: any byte string through the whole front end, as a module and as REPL
// input. A crash, hang, leak or sanitizer report is a bug; diagnostics are expected.
#include <pthread.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "lang/session.h"

namespace {

struct Job {
  std::string text;
};

void* run(void* raw) {
  auto* job = static_cast<Job*>(raw);
  {
    tex::lang::Session session;
    session.loadSource("fuzz.tex", job->text);
  }
  {
    tex::lang::Session session;
    tex::lang::Expr* expr = nullptr;
    if (session.addReplInput(job->text, expr, 1) && expr)
      session.compileExpression(session.replModule(), expr, {{"hit", tex::lang::TypeTable::global().hit()}});
  }
  return nullptr;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Job job{std::string(reinterpret_cast<const char*>(data), size)};
  // The same large stack as the `tex` program gives its front end (cli/main.cpp).
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, size_t(256) << 20);
  pthread_t thread;
  if (pthread_create(&thread, &attr, run, &job) == 0) pthread_join(thread, nullptr);
  pthread_attr_destroy(&attr);
  return 0;
}
