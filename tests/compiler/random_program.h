// A type-directed generator of random, well-typed .tex programs for differential testing of
// the JIT against the reference interpreter (tests/compiler/differential_test.cpp).
//
// A program is a list of module items (imports, type aliases, helper functions, constants and
// exported entry points `e0(h: Hit, ...) -> T`), each a tree of typed nodes. The tree is kept
// (not only the text) so that a failing program can be minimised by replacing subtrees with
// smaller ones of the same type.
//
// What it generates (each production builds a requested type from sub-expressions of known
// types, so programs are valid by construction):
//   values   Bool, Int, Float, Vec2-4, Color, Spectrum, records (nested, aliased, the Hit and
//            the std records), Material, Image; literals with edge values (-0, denormals,
//            huge, inf, nan, 2^24 + 1, INT_MIN, hexadecimal and 1_000 forms)
//   operators + - * / % (with Int->Float promotion and scalar broadcast), comparisons,
//            == != on vectors and colours, && || !, & | ^ << >> ~, unary minus
//   binding  let-in, blocks, annotated lets (with promotion), if / else-if chains (with a
//            block or unparenthesised condition), record literals, updates and fields
//   functions helpers with and without annotations, defaults, named and trailing-comma
//            arguments, Hit parameters (h, a record literal or {h with uv: ...}); lambdas
//            (annotated, capturing, let-bound with a function type, held in records, returned
//            by functions); higher-order helpers taking lambdas, helpers, std functions or
//            builtins (optionally through a function type alias); fold with lambdas and named
//            steps (with defaults, Int accumulators promoted to Float)
//   selects  if-chains over an Int narrowed to a few values (x & 15, (x >> k) & 7, x % 12),
//            what O1 turns into constant tables, with sign choices
//   builtins every prelude builtin of docs/language.md section 6 except the renderer-only
//            corner cases; images from tests/conformance/images
//   std      every exported function of std.math, noise, patterns, color, spectra, materials
//            and gltf (imported by name, renamed, as a module or under an alias)
// Half the programs use no transcendental function (compared bit for bit).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace texdiff {

enum class K { Bool, Int, Float, Vec2, Vec3, Vec4, Color, Spectrum, Record, Material, Image };

struct Ty;
using TyP = std::shared_ptr<const Ty>;
struct Ty {
  K k = K::Float;
  std::vector<std::pair<std::string, TyP>> fields;  // Record: sorted by name
  std::string alias;                                // a `type` alias naming this record, if any
};

TyP basicType(K k);
TyP recordType(std::vector<std::pair<std::string, TyP>> fields, std::string alias = "");
bool sameType(const TyP& a, const TyP& b);
std::string typeText(const TyP& t);  // as written in an annotation (alias if any)
bool isFloatBased(const TyP& t);
int fixedLanes(const TyP& t);  // Float 1, Vec2 2, ..., Color 3; 0 for others (Spectrum: 0)
bool containsKind(const TyP& t, K k);

// A node of a program: its text is parts[0] kids[0] parts[1] kids[1] ... parts[n].
struct Node;
using NodeP = std::shared_ptr<Node>;
struct Node {
  TyP type;                 // null for items and other non-expressions
  std::vector<std::string> parts;
  std::vector<NodeP> kids;
  bool reducible = true;    // may be replaced by a same-typed node when minimising
  bool transcendental = false;  // a call of a transcendental builtin or std function
  std::string entry;        // items: the entry point it defines ("" for other items)
  std::string defines;      // items: the name it defines (helpers, constants, aliases)
};

std::string render(const Node& n);

struct Entry {
  std::string name;
  std::vector<TyP> params;  // after the Hit
  TyP result;
};

struct Program {
  uint64_t seed = 0;
  std::vector<NodeP> items;  // in order; imports are items too
  std::vector<Entry> entries;
  std::string text() const;
};

struct GenOptions {
  int entries = 3;     // exported entry points per program
  int helpers = 3;     // helper functions generated up front (more are made on demand)
  int maxDepth = 5;    // expression depth
  std::string imageDir;  // a directory with quad.png / checker.png for image lookups ("" = none)
};

Program generate(uint64_t seed, const GenOptions& options);

// The simplest expression of type t (a literal), for minimisation.
NodeP simplestValue(const TyP& t);

// A copy of the program in which every float argument x of a transcendental call becomes
// (x + zero), `zero` an expression that is -0.0 at run time but opaque to the compiler: LLVM
// can no longer fold the call with the host's libm, so both sides call the same C library.
// A mismatch that this removes was a transcendental's documented few ulp (amplified).
Program withOpaqueTranscendentalArguments(const Program& p, const std::string& zero);

// Deterministic pseudo-random argument values for entry parameters, as text-free data.
struct ArgValue {
  K k = K::Float;
  float f[4] = {0, 0, 0, 0};  // Float/Vec/Color lanes; Spectrum: one value per lane below
  float spectrum[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  int32_t i = 0;  // Int, Bool
  std::vector<std::pair<std::string, ArgValue>> fields;  // Record (sorted)
};
ArgValue randomArg(const TyP& t, uint64_t seed);
std::string describeArg(const TyP& t, const ArgValue& v);

}  // namespace texdiff
