// Type-directed random .tex programs (random_program.h). Every production below builds an
// expression of a requested type from sub-expressions of known types, following
// docs/language.md (operators and promotions, section 3; typing rules, section 4; builtins,
// section 6) and docs/stdlib.md (the exported signatures of std.*).
#include "random_program.h"

#include <algorithm>
#include <deque>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>

namespace texdiff {

// ---- types ---------------------------------------------------------------------------------

TyP basicType(K k) {
  static const TyP cache[] = {
      std::make_shared<Ty>(Ty{K::Bool, {}, ""}),     std::make_shared<Ty>(Ty{K::Int, {}, ""}),
      std::make_shared<Ty>(Ty{K::Float, {}, ""}),    std::make_shared<Ty>(Ty{K::Vec2, {}, ""}),
      std::make_shared<Ty>(Ty{K::Vec3, {}, ""}),     std::make_shared<Ty>(Ty{K::Vec4, {}, ""}),
      std::make_shared<Ty>(Ty{K::Color, {}, ""}),    std::make_shared<Ty>(Ty{K::Spectrum, {}, ""}),
      nullptr,
      std::make_shared<Ty>(Ty{K::Material, {}, ""}), std::make_shared<Ty>(Ty{K::Image, {}, ""})};
  return cache[int(k)];
}

TyP recordType(std::vector<std::pair<std::string, TyP>> fields, std::string alias) {
  std::sort(fields.begin(), fields.end(), [](auto& a, auto& b) { return a.first < b.first; });
  auto t = std::make_shared<Ty>();
  t->k = K::Record;
  t->fields = std::move(fields);
  t->alias = std::move(alias);
  return t;
}

bool sameType(const TyP& a, const TyP& b) {
  if (a->k != b->k) return false;
  if (a->k != K::Record) return true;
  if (a->fields.size() != b->fields.size()) return false;
  for (size_t i = 0; i < a->fields.size(); ++i)
    if (a->fields[i].first != b->fields[i].first || !sameType(a->fields[i].second, b->fields[i].second)) return false;
  return true;
}

static const char* kindName(K k) {
  switch (k) {
    case K::Bool: return "Bool";
    case K::Int: return "Int";
    case K::Float: return "Float";
    case K::Vec2: return "Vec2";
    case K::Vec3: return "Vec3";
    case K::Vec4: return "Vec4";
    case K::Color: return "Color";
    case K::Spectrum: return "Spectrum";
    case K::Material: return "Material";
    case K::Image: return "Image";
    case K::Record: return "Record";
  }
  return "?";
}

std::string typeText(const TyP& t) {
  if (t->k != K::Record) return kindName(t->k);
  if (!t->alias.empty()) return t->alias;
  std::string s = "{";
  for (size_t i = 0; i < t->fields.size(); ++i) s += (i ? ", " : "") + t->fields[i].first + ": " + typeText(t->fields[i].second);
  return s + "}";
}

bool isFloatBased(const TyP& t) {
  return t->k == K::Float || t->k == K::Vec2 || t->k == K::Vec3 || t->k == K::Vec4 || t->k == K::Color ||
         t->k == K::Spectrum;
}

int fixedLanes(const TyP& t) {
  switch (t->k) {
    case K::Float: return 1;
    case K::Vec2: return 2;
    case K::Vec3: return 3;
    case K::Vec4: return 4;
    case K::Color: return 3;
    default: return 0;
  }
}

bool containsKind(const TyP& t, K k) {
  if (t->k == k) return true;
  for (auto& f : t->fields)
    if (containsKind(f.second, k)) return true;
  return false;
}

// ---- nodes ---------------------------------------------------------------------------------

static void renderInto(const Node& n, std::string& out) {
  for (size_t i = 0; i < n.parts.size(); ++i) {
    out += n.parts[i];
    if (i < n.kids.size()) renderInto(*n.kids[i], out);
  }
}

std::string render(const Node& n) {
  std::string s;
  renderInto(n, s);
  return s;
}

std::string Program::text() const {
  std::string s;
  for (auto& item : items) s += render(*item);
  return s;
}

// A node from a format in which each '$' stands for the next kid.
static NodeP mk(TyP t, const std::string& format, std::vector<NodeP> kids = {}) {
  auto n = std::make_shared<Node>();
  n->type = std::move(t);
  std::string part;
  for (char c : format) {
    if (c == '$') {
      n->parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  n->parts.push_back(part);
  n->kids = std::move(kids);
  if (n->parts.size() != n->kids.size() + 1) {
    std::fprintf(stderr, "random_program: format '%s' has %zu holes for %zu kids\n", format.c_str(), n->parts.size() - 1,
                 n->kids.size());
    std::abort();
  }
  return n;
}

static std::string floatText(float x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "(-inf)";
  if (x == 0) return std::signbit(x) ? "(-0.0)" : "0.0";
  char buf[64];
  // The shortest of %.6g .. %.9g that reads back as x.
  for (int digits = 6; digits <= 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, double(std::fabs(x)));
    if (std::strtof(buf, nullptr) == std::fabs(x)) break;
  }
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  // "1e+38" is fine for the lexer; a mantissa without a '.' before 'e' too ("1e6").
  return x < 0 ? "(-" + s + ")" : s;
}

static std::string intText(int32_t v) {
  if (v == std::numeric_limits<int32_t>::min()) return "(-2147483648)";
  if (v < 0) return "(-" + std::to_string(-int64_t(v)) + ")";
  // Now and then hexadecimal or with underscores (section 1), decided by the value's bits.
  if (v > 9 && (v * 2654435761u >> 28) == 3) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%x", unsigned(v));
    return buf;
  }
  if (v > 999 && (v * 2654435761u >> 28) == 5) {
    std::string s = std::to_string(v), out;
    for (size_t i = 0; i < s.size(); ++i) {
      if (i > 0 && (s.size() - i) % 3 == 0) out += '_';
      out += s[i];
    }
    return out;
  }
  return std::to_string(v);
}

NodeP simplestValue(const TyP& t) {
  switch (t->k) {
    case K::Bool: return mk(t, "true");
    case K::Int: return mk(t, "0");
    case K::Float: return mk(t, "0.0");
    case K::Vec2: return mk(t, "vec2(0.0)");
    case K::Vec3: return mk(t, "vec3(0.0)");
    case K::Vec4: return mk(t, "vec4(0.0)");
    case K::Color: return mk(t, "rgb(0.0)");
    case K::Spectrum: return mk(t, "spectrum(0.0)");
    case K::Material: return mk(t, "diffuse(rgb(0.5))");
    case K::Image: return nullptr;
    case K::Record: {
      std::string f = "{";
      std::vector<NodeP> kids;
      for (size_t i = 0; i < t->fields.size(); ++i) {
        f += (i ? ", " : "") + t->fields[i].first + ": $";
        NodeP k = simplestValue(t->fields[i].second);
        if (!k) return nullptr;
        kids.push_back(k);
      }
      return mk(t, f + "}", kids);
    }
  }
  return nullptr;
}

// ---- the standard library's exported signatures (docs/stdlib.md) ---------------------------

// Type codes: F Float, I Int, B Bool, 2/3/4 VecN, C Color, S Spectrum, M Material, H Hit,
// c cellular {cell: Vec3, f1, f2}, d cellular2 {cell: Vec2, f1, f2}, k brick {id, local, mortar},
// t tile {grout, id, local}, f (Vec3) -> Float, g (Vec2) -> Float. A '?' after the code marks
// a parameter with a default.
struct StdFn {
  const char* module;
  const char* name;
  const char* params;  // "F:x F?:n"
  char result;
  int cost;  // rough interpretation cost (a perlin is 4)
  bool transcendental;
};

static const std::vector<StdFn>& stdFns() {
  static const std::vector<StdFn> table = {
      // std.math
      {"math", "saturate", "F:x", 'F', 1, false},
      {"math", "inverse_mix", "F:a F:b F:x", 'F', 1, false},
      {"math", "remap", "F:x F:a F:b F:c F:d", 'F', 1, false},
      {"math", "remap_clamped", "F:x F:a F:b F:c F:d", 'F', 1, false},
      {"math", "linearstep", "F:e0 F:e1 F:x", 'F', 1, false},
      {"math", "smootherstep", "F:e0 F:e1 F:x", 'F', 1, false},
      {"math", "bias", "F:x F:b", 'F', 1, true},
      {"math", "gain", "F:x F:g", 'F', 1, true},
      {"math", "pulse", "F:a F:b F:x", 'F', 1, false},
      {"math", "bump", "F:c F:w F:x", 'F', 1, false},
      {"math", "triangle_wave", "F:x", 'F', 1, false},
      {"math", "sawtooth", "F:x", 'F', 1, false},
      {"math", "radians", "F:deg", 'F', 1, false},
      {"math", "degrees", "F:rad", 'F', 1, false},
      {"math", "rotate2", "2:v F:angle", '2', 1, true},
      {"math", "rotate3", "3:v 3:axis F:angle", '3', 1, true},
      {"math", "max_component", "3:v", 'F', 1, false},
      {"math", "min_component", "3:v", 'F', 1, false},
      {"math", "to_polar", "2:v", '2', 1, true},
      {"math", "hash", "I:x", 'I', 1, false},
      {"math", "hash2i", "I:x I:y I?:seed", 'I', 1, false},
      {"math", "hash3i", "I:x I:y I:z I?:seed", 'I', 1, false},
      {"math", "unit_float", "I:h", 'F', 1, false},
      {"math", "hash01", "I:x", 'F', 1, false},
      {"math", "hash21", "2:p", 'F', 1, false},
      {"math", "hash22", "2:p", '2', 1, false},
      {"math", "hash23", "2:p", '3', 1, false},
      {"math", "hash31", "3:p", 'F', 1, false},
      {"math", "hash33", "3:p", '3', 1, false},
      // std.noise
      {"noise", "perlin", "3:p", 'F', 4, false},
      {"noise", "perlin2", "2:p", 'F', 3, false},
      {"noise", "simplex", "3:p", 'F', 4, false},
      {"noise", "simplex2", "2:p", 'F', 3, false},
      {"noise", "value_noise", "3:p", 'F', 4, false},
      {"noise", "value_noise2", "2:p", 'F', 3, false},
      {"noise", "worley", "3:p F?:jitter", 'F', 20, false},
      {"noise", "worley2", "2:p F?:jitter", 'F', 8, false},
      {"noise", "worley_edge", "3:p F?:jitter", 'F', 20, false},
      {"noise", "worley_edge2", "2:p F?:jitter", 'F', 8, false},
      {"noise", "cellular", "3:p F?:jitter", 'c', 25, false},
      {"noise", "cellular2", "2:p F?:jitter", 'd', 10, false},
      {"noise", "fbm", "I:octaves f:f 3:p F?:lacunarity F?:gain", 'F', 16, true},
      {"noise", "turbulence", "I:octaves f:f 3:p F?:lacunarity F?:gain", 'F', 16, true},
      {"noise", "ridged", "I:octaves f:f 3:p F?:lacunarity F?:gain F?:offset", 'F', 16, true},
      {"noise", "fbm2", "I:octaves g:f 2:p F?:lacunarity F?:gain", 'F', 12, true},
      {"noise", "turbulence2", "I:octaves g:f 2:p F?:lacunarity F?:gain", 'F', 12, true},
      {"noise", "ridged2", "I:octaves g:f 2:p F?:lacunarity F?:gain F?:offset", 'F', 12, true},
      {"noise", "warp", "3:p F:amount I?:octaves", '3', 50, true},
      {"noise", "warp2", "2:p F:amount I?:octaves", '2', 30, true},
      // std.patterns
      {"patterns", "checker", "2:uv F?:n", 'F', 1, false},
      {"patterns", "checker3", "3:p F?:n", 'F', 1, false},
      {"patterns", "stripes", "F:x F?:n F?:duty", 'F', 1, false},
      {"patterns", "soft_stripes", "F:x F?:n", 'F', 1, true},
      {"patterns", "grid", "2:uv F?:n F?:width", 'F', 1, false},
      {"patterns", "dots", "2:uv F?:n F?:radius", 'F', 1, false},
      {"patterns", "gradient", "2:uv 2?:a 2?:b", 'F', 1, false},
      {"patterns", "radial_gradient", "2:uv 2?:center F?:radius", 'F', 1, false},
      {"patterns", "angular_gradient", "2:uv 2?:center", 'F', 1, true},
      {"patterns", "brick", "2:uv 2?:size F?:mortar F?:offset", 'k', 2, false},
      {"patterns", "bricks", "2:uv 2?:size F?:mortar F?:offset", 'F', 2, false},
      {"patterns", "brick_id", "2:uv 2?:size F?:offset", '2', 2, false},
      {"patterns", "brick_random", "2:uv 2?:size F?:offset", 'F', 2, false},
      {"patterns", "brick_color", "2:uv C:base F?:variation 2?:size F?:offset", 'C', 3, false},
      {"patterns", "tile", "2:uv F?:n F?:grout", 't', 2, false},
      {"patterns", "tiles", "2:uv F?:n F?:grout", 'F', 2, false},
      {"patterns", "tile_color", "2:uv C:base C:grout_color F?:n F?:grout F?:variation", 'C', 3, false},
      {"patterns", "wood", "3:p F?:rings F?:noise", 'F', 20, true},
      {"patterns", "wood_color", "3:p C?:light C?:dark F?:rings F?:noise F?:grain", 'C', 35, true},
      {"patterns", "marble", "3:p F?:frequency F?:strength F?:sharpness 3?:direction", 'F', 30, true},
      {"patterns", "marble_color", "3:p C?:base C?:vein_color F?:frequency F?:strength F?:sharpness", 'C', 30, true},
      // std.color
      {"color", "srgb_to_linear", "C:c", 'C', 1, true},
      {"color", "linear_to_srgb", "C:c", 'C', 1, true},
      {"color", "srgb", "F:r F:g F:b", 'C', 1, true},
      {"color", "srgb_hex", "I:code", 'C', 1, true},
      {"color", "hsv", "F:h F:s F:v", 'C', 1, false},
      {"color", "rgb_to_hsv", "C:c", '3', 1, false},
      {"color", "saturation", "C:c F:s", 'C', 1, false},
      // std.spectra
      {"spectra", "blackbody", "F:kelvin", 'S', 1, true},
      {"spectra", "illuminant_a", "", 'S', 1, true},
      {"spectra", "cauchy", "F:a F:b_nm2", 'S', 1, false},
      {"spectra", "sellmeier", "F:b1 F:b2 F:b3 F:c1_um2 F:c2_um2 F:c3_um2", 'S', 1, false},
      {"spectra", "bk7", "", 'S', 1, false},
      {"spectra", "sf11", "", 'S', 1, false},
      {"spectra", "gold_eta", "", 'S', 2, false},
      {"spectra", "gold_k", "", 'S', 2, false},
      {"spectra", "silver_eta", "", 'S', 2, false},
      {"spectra", "silver_k", "", 'S', 2, false},
      {"spectra", "copper_eta", "", 'S', 2, false},
      {"spectra", "copper_k", "", 'S', 2, false},
      {"spectra", "aluminium_eta", "", 'S', 2, false},
      {"spectra", "aluminium_k", "", 'S', 2, false},
      {"spectra", "cie_d65", "", 'S', 3, false},
      // std.gltf
      {"gltf", "dispersive_ior", "F:ior F:dispersion", 'S', 1, false},
      {"gltf", "gulbrandsen_eta", "S:r S:g", 'S', 1, false},
      {"gltf", "gulbrandsen_k", "S:r S:g", 'S', 1, false},
      {"gltf", "metallic_roughness", "H:h C:base F:metallic F:roughness F:transmission F:ior F:dispersion C:emission_rgb", 'M', 3, true},
      {"gltf", "metallic_roughness_walls",
       "H:h C:base F:metallic F:roughness F:transmission F:ior F:dispersion B:thin_walled C:emission_rgb", 'M', 3, true},
      // std.materials
      {"materials", "plastic", "C:color F?:roughness", 'M', 1, false},
      {"materials", "glossy_plastic", "C:color F?:n", 'M', 1, false},
      {"materials", "metal", "S:eta S:k F?:roughness", 'M', 1, false},
      {"materials", "gold", "F?:roughness", 'M', 4, false},
      {"materials", "silver", "F?:roughness", 'M', 4, false},
      {"materials", "copper", "F?:roughness", 'M', 4, false},
      {"materials", "aluminium", "F?:roughness", 'M', 4, false},
      {"materials", "glass", "F?:ior", 'M', 1, false},
      {"materials", "frosted_glass", "F:roughness F?:ior", 'M', 1, false},
      {"materials", "bk7_glass", "F?:roughness", 'M', 1, false},
      {"materials", "sf11_glass", "F?:roughness", 'M', 1, false},
      {"materials", "lamp", "F:kelvin F?:power", 'M', 1, true},
      {"materials", "velvet", "C:color F?:roughness", 'M', 1, true},
  };
  return table;
}

struct StdParam {
  char code;
  bool optional;
  std::string name;
};

static std::vector<StdParam> parseParams(const char* spec) {
  std::vector<StdParam> out;
  std::istringstream in(spec);
  std::string word;
  while (in >> word) {
    StdParam p;
    p.code = word[0];
    p.optional = word[1] == '?';
    p.name = word.substr(word.find(':') + 1);
    out.push_back(p);
  }
  return out;
}

static TyP hitType() {
  static TyP hit = recordType({{"p", basicType(K::Vec3)},
                               {"n", basicType(K::Vec3)},
                               {"uv", basicType(K::Vec2)},
                               {"dpdx", basicType(K::Vec3)},
                               {"dpdy", basicType(K::Vec3)},
                               {"duvdx", basicType(K::Vec2)},
                               {"duvdy", basicType(K::Vec2)}},
                              "Hit");
  return hit;
}

static TyP codeType(char c) {
  switch (c) {
    case 'F': return basicType(K::Float);
    case 'I': return basicType(K::Int);
    case 'B': return basicType(K::Bool);
    case '2': return basicType(K::Vec2);
    case '3': return basicType(K::Vec3);
    case '4': return basicType(K::Vec4);
    case 'C': return basicType(K::Color);
    case 'S': return basicType(K::Spectrum);
    case 'M': return basicType(K::Material);
    case 'H': return hitType();
    case 'c': return recordType({{"cell", basicType(K::Vec3)}, {"f1", basicType(K::Float)}, {"f2", basicType(K::Float)}});
    case 'd': return recordType({{"cell", basicType(K::Vec2)}, {"f1", basicType(K::Float)}, {"f2", basicType(K::Float)}});
    case 'k': return recordType({{"id", basicType(K::Vec2)}, {"local", basicType(K::Vec2)}, {"mortar", basicType(K::Float)}});
    case 't': return recordType({{"grout", basicType(K::Float)}, {"id", basicType(K::Vec2)}, {"local", basicType(K::Vec2)}});
  }
  return nullptr;
}

// ---- the generator -------------------------------------------------------------------------

namespace {

float edgeFloat(std::mt19937_64& rng) {
  static const float edges[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, 2.0f, 1e38f, -1e38f, 3.40282347e38f, -3.40282347e38f,
                                1.17549435e-38f, 1e-38f, 1e-40f, -1e-40f, 1.4e-45f, -1.4e-45f,
                                std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                std::numeric_limits<float>::quiet_NaN(), 16777216.0f, 16777217.0f, 8388608.5f, 0.49999997f,
                                2147483648.0f, -2147483648.0f, 2147483520.0f, 4294967296.0f, 1e10f, -1e-10f, 65536.0f,
                                65537.5f, 1e5f, 3.14159265f, 1.5707964f, 100000.5f, 1.0000001f, 0.99999994f, -2.5f, 2.5f,
                                0.1f, 1e20f, 1e-20f, 1e30f};
  return edges[std::uniform_int_distribution<size_t>(0, std::size(edges) - 1)(rng)];
}

float randomFloat(std::mt19937_64& rng) {
  double r = std::uniform_real_distribution<double>(0, 1)(rng);
  if (r < 0.35) {
    static const float nice[] = {0.0f, 1.0f, 0.5f, 2.0f, -1.0f, 0.25f, 3.0f, 10.0f, 0.1f, 0.75f, 4.0f, -0.5f, 8.0f, 1.5f};
    return nice[std::uniform_int_distribution<size_t>(0, std::size(nice) - 1)(rng)];
  }
  if (r < 0.65) return float(std::round(std::uniform_real_distribution<double>(-10, 10)(rng) * 1000) / 1000);
  if (r < 0.85) return edgeFloat(rng);
  // Any exponent, any sign.
  int e = std::uniform_int_distribution<int>(-149, 127)(rng);
  double m = std::uniform_real_distribution<double>(1, 2)(rng);
  float x = float(std::ldexp(m, e));
  return std::uniform_int_distribution<int>(0, 1)(rng) ? -x : x;
}

int32_t randomInt(std::mt19937_64& rng) {
  double r = std::uniform_real_distribution<double>(0, 1)(rng);
  if (r < 0.45) return std::uniform_int_distribution<int32_t>(0, 9)(rng);
  if (r < 0.6) return std::uniform_int_distribution<int32_t>(-9, -1)(rng);
  if (r < 0.85) {
    static const int32_t edges[] = {2147483647, -2147483647 - 1, 31, 32, 33, 63, 64, -1, -31, -32, 255, 65535, 65536,
                                    46341, 0x7fffffff, 0x55555555, 12345, 1 << 24, (1 << 24) + 1, -(1 << 30), 1000000};
    return edges[std::uniform_int_distribution<size_t>(0, std::size(edges) - 1)(rng)];
  }
  return int32_t(uint32_t(rng()));
}

class Gen {
 public:
  Gen(uint64_t seed, const GenOptions& o) : rng_(seed * 0x9E3779B97F4A7C15ull + 12345), options_(o) {
    program_.seed = seed;
    // Half the programs use no transcendental function, so that they are compared bit for bit.
    exactOnly_ = chance(0.5);
  }

  Program run() {
    chooseImportStyles();
    // Module-level constants first (no Hit), then helpers, then entries.
    int constants = uni(0, 2);
    for (int i = 0; i < constants; ++i) makeConstant();
    for (int i = 0; i < options_.helpers; ++i) makeHelper(randomType(1, false), chance(0.5), chance(0.2));
    for (int i = 0; i < options_.entries; ++i) makeEntry(i);
    // Imports go first.
    std::vector<NodeP> items;
    for (auto& [module, names] : imported_) {
      int style = importStyle_[module];
      if (style == 0) {
        std::string list;
        for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
        auto n = mk(nullptr, "import std." + module + ".{" + list + "}\n");
        n->reducible = false;
        items.push_back(n);
      } else {
        auto n = mk(nullptr, "import std." + module + (style == 1 ? " as " + alias(module) : "") + "\n");
        n->reducible = false;
        items.push_back(n);
      }
    }
    for (auto& i : items_) items.push_back(i);
    program_.items = std::move(items);
    return program_;
  }

 private:
  struct Var {
    std::string name;
    TyP type;
  };
  struct Callable {
    std::string name;
    std::vector<TyP> params;
    TyP result;
  };
  struct Helper {
    std::string name;
    std::vector<TyP> params;  // the intended argument types (after the Hit, if any)
    std::vector<std::string> paramNames;
    int firstDefault = -1;  // params from here on have defaults
    bool annotated = false;
    bool takesHit = false;
    bool higherOrder = false;  // the first parameter is a function
    Callable fparam;           // higher order: its signature
    TyP result;
    int foldDepth = 0;
    int cost = 0;
    bool stepShape = false;  // (acc: result, i: Int, defaults...) -> result: usable as a fold step
  };
  struct Scope {
    std::vector<Var> vars;
    std::vector<Callable> callables;
    bool hit = false;
    int foldDepth = 0;
    int costMultiplier = 1;
  };

  // ---- randomness
  int uni(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double real() { return std::uniform_real_distribution<double>(0, 1)(rng_); }
  bool chance(double p) { return real() < p; }
  template <typename T>
  const T& pick(const std::vector<T>& v) {
    return v[size_t(uni(0, int(v.size()) - 1))];
  }
  // Index by weights.
  int weighted(std::initializer_list<double> w) {
    double total = 0;
    for (double x : w) total += x;
    double r = real() * total;
    int i = 0;
    for (double x : w) {
      if (r < x) return i;
      r -= x;
      ++i;
    }
    return int(w.size()) - 1;
  }
  std::string fresh(const char* prefix) { return prefix + std::to_string(counter_++); }

  // ---- imports
  void chooseImportStyles() {
    for (const char* m : {"math", "noise", "patterns", "color", "spectra", "materials", "gltf"}) {
      int style = uni(0, 2);
      if (std::string(m) == "color" && style == 2) style = 1;  // `color` would shadow the builtin color(v)
      importStyle_[m] = style;
    }
  }
  std::string alias(const std::string& module) { return "m_" + module; }
  // The text that names std function `name` of `module` at a call, importing it.
  std::string stdName(const std::string& module, const std::string& name) {
    int style = importStyle_[module];
    if (style == 0) {
      // import std.m.{name as name_r}, decided once per name
      bool renamed = (std::hash<std::string>{}(name) + program_.seed) % 4 == 0;
      imported_[module].insert(renamed ? name + " as " + name + "_r" : name);
      return renamed ? name + "_r" : name;
    }
    imported_[module].insert(name);
    if (style == 1) return alias(module) + "." + name;
    return module + "." + name;
  }

  // ---- types
  TyP randomType(int recordDepth, bool allowMaterial) {
    int w = weighted({30, 14, 8, 8, 10, 4, 8, 7, double(recordDepth > 0 ? 6 : 0), allowMaterial ? 2.0 : 0.0,
                      options_.imageDir.empty() ? 0.0 : 0.5});
    static const K kinds[] = {K::Float, K::Int, K::Bool, K::Vec2, K::Vec3, K::Vec4, K::Color, K::Spectrum, K::Record, K::Material, K::Image};
    if (kinds[w] == K::Record) return randomRecord(recordDepth - 1, nullptr);
    return basicType(kinds[w]);
  }
  // A record type; with `mustHave` one of its fields has that type.
  TyP randomRecord(int depth, const TyP& mustHave) {
    if (!mustHave && chance(0.15)) return codeType(pick(std::vector<char>{'c', 'd', 'k', 't'}));
    static const std::vector<std::string> names = {"a", "b", "c", "d", "e", "uv", "p"};
    std::vector<std::string> pool = names;
    std::shuffle(pool.begin(), pool.end(), rng_);
    int count = uni(1, 3);
    std::vector<std::pair<std::string, TyP>> fields;
    for (int i = 0; i < count; ++i) fields.push_back({pool[size_t(i)], randomType(depth, false)});
    if (mustHave) fields[size_t(uni(0, count - 1))].second = mustHave;
    TyP t = recordType(fields);
    if (chance(0.3)) {
      // A type alias for it.
      std::string name = "R" + std::to_string(counter_++);
      auto item = mk(nullptr, "type " + name + " = " + typeText(t) + "\n");
      item->reducible = false;
      item->defines = name;
      pending_.push_back(item);
      t = recordType(fields, name);
    }
    return t;
  }

  // ---- literals and leaves
  NodeP floatLit() { return mk(basicType(K::Float), floatText(randomFloat(rng_))); }
  NodeP intLit() { return mk(basicType(K::Int), intText(randomInt(rng_))); }

  NodeP literal(const TyP& t) {
    switch (t->k) {
      case K::Bool: return mk(t, chance(0.5) ? "true" : "false");
      case K::Int: return intLit();
      case K::Float: return floatLit();
      case K::Vec2:
      case K::Vec3:
      case K::Vec4: {
        int n = fixedLanes(t);
        std::string name = "vec" + std::to_string(n);
        if (chance(0.3)) return mk(t, name + "($)", {floatLit()});
        std::string f = name + "(";
        std::vector<NodeP> kids;
        for (int i = 0; i < n; ++i) {
          f += i ? ", $" : "$";
          kids.push_back(floatLit());
        }
        return mk(t, f + ")", kids);
      }
      case K::Color:
        if (chance(0.3)) return mk(t, "rgb($)", {floatLit()});
        return mk(t, "rgb($, $, $)", {floatLit(), floatLit(), floatLit()});
      case K::Spectrum:
        if (chance(0.5)) return mk(t, "lambda_nm");
        return mk(t, "spectrum($)", {floatLit()});
      case K::Material: return mk(t, "diffuse($)", {literal(basicType(K::Color))});
      case K::Image: return imageLit();
      case K::Record: {
        std::string f = "{";
        std::vector<NodeP> kids;
        auto fields = t->fields;
        std::shuffle(fields.begin(), fields.end(), rng_);
        for (size_t i = 0; i < fields.size(); ++i) {
          f += (i ? ", " : "") + fields[i].first + ": $";
          kids.push_back(leaf(fields[i].second));
        }
        return mk(t, f + "}", kids);
      }
    }
    return nullptr;
  }

  NodeP imageLit() {
    static const std::vector<std::string> files = {"quad.png", "checker.png", "odd.png", "hdr.exr", "lum.exr"};
    return mk(basicType(K::Image), std::string(chance(0.5) ? "image" : "image_data") + "(\"" + options_.imageDir + "/" +
                                       pick(files) + "\")");
  }

  std::vector<const Var*> varsOf(const TyP& t) {
    std::vector<const Var*> out;
    for (auto& v : scope_.vars)
      if (sameType(v.type, t)) out.push_back(&v);
    for (auto& v : globals_)
      if (sameType(v.type, t)) out.push_back(&v);
    return out;
  }

  NodeP hitField(const TyP& t) {
    if (!scope_.hit) return nullptr;
    if (t->k == K::Vec2) return mk(t, pick(std::vector<std::string>{"h.uv", "h.uv", "h.duvdx", "h.duvdy"}));
    if (t->k == K::Vec3) return mk(t, pick(std::vector<std::string>{"h.p", "h.p", "h.n", "h.dpdx", "h.dpdy"}));
    if (t->k == K::Float)
      return mk(t, pick(std::vector<std::string>{"h.uv.x", "h.uv.y", "h.p.x", "h.p.y", "h.p.z", "h.n.z", "h.uv.y", "h.dpdx.x"}));
    return nullptr;
  }

  NodeP leaf(const TyP& t) {
    auto vars = varsOf(t);
    if (!vars.empty() && chance(0.55)) return mk(t, pick(vars)->name);
    if (NodeP h = hitField(t); h && chance(0.6)) return h;
    if (t->k == K::Record) {
      // A record leaf that is not a literal: a Hit-typed parameter when asked for a Hit.
      if (sameType(t, hitType()) && scope_.hit && chance(0.7)) return mk(t, "h");
    }
    return literal(t);
  }

  // ---- expressions
  NodeP expr(const TyP& t, int d) {
    if (d <= 0) return leaf(t);
    double r = real();
    if (r < 0.08) return leaf(t);
    if (r < 0.32)
      if (NodeP n = structural(t, d)) return n;
    switch (t->k) {
      case K::Float: return floatExpr(d);
      case K::Int: return intExpr(d);
      case K::Bool: return boolExpr(d);
      case K::Vec2:
      case K::Vec3:
      case K::Vec4: return vecExpr(t, d);
      case K::Color: return colorExpr(d);
      case K::Spectrum: return spectrumExpr(d);
      case K::Record: return recordExpr(t, d);
      case K::Material: return materialExpr(d);
      case K::Image: return chance(0.8) ? imageLit() : leaf(t);
    }
    return leaf(t);
  }

  // An argument for a place that accepts type t after promotion (an annotated parameter):
  // sometimes an Int for a Float, a Float for a Spectrum.
  NodeP promotable(const TyP& t, int d) {
    if (t->k == K::Float && chance(0.1)) return expr(basicType(K::Int), d);
    if (t->k == K::Spectrum && chance(0.2)) return expr(chance(0.8) ? basicType(K::Float) : basicType(K::Int), d);
    return expr(t, d);
  }

  NodeP structural(const TyP& t, int d) {
    bool canFold = scope_.foldDepth < 2 && t->k != K::Image;
    switch (weighted({3, 2, 3.5, 3, 2, 1.2, canFold ? 2.0 : 0.0, 1.5, 0.6, 0.6, 0.5})) {
      case 0: return letIn(t, d);
      case 1: return block(t, d);
      case 2: return ifElse(t, d);
      case 3: return helperCall(t, d);
      case 4: return lambdaCall(t, d);
      case 5: return higherOrderCall(t, d);
      case 6: return fold(t, d);
      case 7: return fieldOf(t, d);
      case 8: return callableLocal(t, d);
      case 9: return factoryCall(t, d);
      case 10: return recordHeldLambda(t, d);
    }
    return nullptr;
  }

  // fn gN(x..) = (|q..| body): a function returning a lambda that captures its parameters,
  // called as gN(args)(lambda args).
  NodeP factoryCall(const TyP& t, int d) {
    if (scope_.foldDepth > 0 || helpers_.size() >= 14 || depthOfHelpers_ >= 2 || factories_ >= 3) return nullptr;
    ++factories_;
    std::vector<TyP> params, lambdaParams;
    for (int i = uni(1, 2); i > 0; --i) params.push_back(randomType(0, false));
    for (int i = uni(0, 2); i > 0; --i) lambdaParams.push_back(randomType(0, false));
    std::string name = fresh("g");
    Scope saved = scope_;
    int savedCost = cost_;
    scope_ = Scope{};
    ++depthOfHelpers_;
    std::string f = "fn " + name + "(";
    std::vector<std::string> names;
    for (size_t i = 0; i < params.size(); ++i) {
      names.push_back(fresh("x"));
      f += (i ? ", " : "") + names.back();
      scope_.vars.push_back({names.back(), params[i]});
    }
    NodeP body = makeLambda(lambdaParams, t, options_.maxDepth - 2, false);
    --depthOfHelpers_;
    scope_ = saved;
    cost_ = savedCost + 2;
    auto item = mk(nullptr, f + ") = $\n", {body});
    item->reducible = false;
    item->defines = name;
    pending_.push_back(item);
    std::string call = name + "(";
    std::vector<NodeP> kids;
    for (size_t i = 0; i < params.size(); ++i) {
      call += i ? ", $" : "$";
      kids.push_back(expr(params[i], d - 1));
    }
    call += ")(";
    for (size_t i = 0; i < lambdaParams.size(); ++i) {
      call += i ? ", $" : "$";
      kids.push_back(expr(lambdaParams[i], d - 1));
    }
    return mk(t, call + ")", kids);
  }

  // ({f: (|q| body), a: e}).f(arg): a lambda stored in a record, or bound with a function
  // type annotation (whose parameter types convert the arguments).
  NodeP recordHeldLambda(const TyP& t, int d) {
    std::vector<TyP> params;
    for (int i = uni(0, 2); i > 0; --i) params.push_back(randomType(0, false));
    NodeP lambda = makeLambda(params, t, d - 1, false);
    std::string args;
    std::vector<NodeP> kids = {lambda};
    if (chance(0.5) && t->k != K::Image) {
      bool ok = true;
      std::string sig = "(";
      for (size_t i = 0; i < params.size(); ++i) {
        sig += (i ? ", " : "") + typeText(params[i]);
        ok = ok && params[i]->k != K::Image;
      }
      sig += ") -> " + typeText(t);
      if (ok) {
        std::string name = fresh("l");
        std::string f = "(let " + name + ": " + sig + " = $ in " + name + "(";
        for (size_t i = 0; i < params.size(); ++i) {
          f += i ? ", $" : "$";
          kids.push_back(promotable(params[i], d - 1));
        }
        return mk(t, f + "))", kids);
      }
    }
    std::string f = "({f: $, a: $}).f(";
    kids.push_back(expr(basicType(K::Float), d - 2));
    for (size_t i = 0; i < params.size(); ++i) {
      f += i ? ", $" : "$";
      kids.push_back(expr(params[i], d - 1));
    }
    return mk(t, f + ")", kids);
  }

  NodeP letIn(const TyP& t, int d) {
    TyP bt = randomType(1, true);
    std::string name = fresh("v");
    NodeP value;
    std::string annotation;
    if (chance(0.25) && bt->k != K::Image) {
      annotation = ": " + typeText(bt);
      value = promotable(bt, d - 1);
    } else {
      value = expr(bt, d - 1);
    }
    scope_.vars.push_back({name, bt});
    NodeP body = expr(t, d - 1);
    scope_.vars.pop_back();
    return mk(t, "(let " + name + annotation + " = $ in $)", {value, body});
  }

  NodeP block(const TyP& t, int d) {
    int lets = uni(1, 3);
    std::string f = "{ ";
    std::vector<NodeP> kids;
    for (int i = 0; i < lets; ++i) {
      TyP bt = randomType(1, true);
      std::string name = fresh("v");
      std::string annotation;
      if (chance(0.2) && bt->k != K::Image) {
        annotation = ": " + typeText(bt);
        kids.push_back(promotable(bt, d - 1));
      } else {
        kids.push_back(expr(bt, d - 1));
      }
      f += "let " + name + annotation + " = $; ";
      scope_.vars.push_back({name, bt});
    }
    kids.push_back(expr(t, d - 1));
    for (int i = 0; i < lets; ++i) scope_.vars.pop_back();
    return mk(t, f + "$ }", kids);
  }

  NodeP ifElse(const TyP& t, int d) {
    auto branch = [&]() {
      // An Int branch of a Float if is promoted (section 4.1).
      if (t->k == K::Float && chance(0.1)) return expr(basicType(K::Int), d - 1);
      return expr(t, d - 1);
    };
    if (chance(0.1)) {
      // A block as the condition, and a condition without parentheses (section 2).
      NodeP c = chance(0.5) ? block(basicType(K::Bool), d - 1) : expr(basicType(K::Bool), d - 1), a = branch(), b = branch();
      if (!sameType(a->type, t) && !sameType(b->type, t)) b = expr(t, d - 1);
      if (render(*c).find('{') == std::string::npos || render(*c).rfind("{ let", 0) == 0)
        return mk(t, "(if $ { $ } else { $ })", {c, a, b});
      return mk(t, "(if ($) { $ } else { $ })", {c, a, b});
    }
    if (chance(0.25)) {
      NodeP c1 = expr(basicType(K::Bool), d - 1), a = branch(), c2 = expr(basicType(K::Bool), d - 1), b = branch(), c = branch();
      if (!sameType(a->type, t) && !sameType(b->type, t) && !sameType(c->type, t)) c = expr(t, d - 1);
      return mk(t, "(if ($) { $ } else if ($) { $ } else { $ })", {c1, a, c2, b, c});
    }
    NodeP c = expr(basicType(K::Bool), d - 1), a = branch(), b = branch();
    if (!sameType(a->type, t) && !sameType(b->type, t)) b = expr(t, d - 1);
    return mk(t, "(if ($) { $ } else { $ })", {c, a, b});
  }

  NodeP fieldOf(const TyP& t, int d) {
    TyP r = randomRecord(0, t);
    for (auto& f : r->fields)
      if (sameType(f.second, t)) return mk(t, "($)." + f.first, {expr(r, d - 1)});
    return nullptr;
  }

  // A call of a lambda or function parameter in scope whose result is t.
  NodeP callableLocal(const TyP& t, int d) {
    std::vector<const Callable*> fits;
    for (auto& c : scope_.callables)
      if (sameType(c.result, t)) fits.push_back(&c);
    if (fits.empty()) return nullptr;
    const Callable c = *pick(fits);  // a copy: generating the arguments may add callables
    return callWith(t, c.name, c.params, d);
  }

  NodeP callWith(const TyP& t, const std::string& name, const std::vector<TyP>& params, int d) {
    std::string f = name + "(";
    std::vector<NodeP> kids;
    for (size_t i = 0; i < params.size(); ++i) {
      f += i ? ", $" : "$";
      kids.push_back(expr(params[i], d - 1));
    }
    return mk(t, f + ")", kids);
  }

  NodeP lambdaCall(const TyP& t, int d) {
    std::vector<TyP> params;
    int n = uni(0, 2);
    for (int i = 0; i < n; ++i) params.push_back(randomType(1, false));
    std::string name = fresh("l");
    NodeP lambda = makeLambda(params, t, d - 1, false);
    scope_.callables.push_back({name, params, t});
    NodeP use;
    if (isFloatBased(t) && chance(0.3)) {
      use = mk(t, "($ + $)", {callWith(t, name, params, d - 1), callWith(t, name, params, d - 1)});
    } else {
      use = expr(t, d - 1);
      // The body may not have used it: call it at least once.
      if (chance(0.7)) use = callWith(t, name, params, d - 1);
    }
    scope_.callables.pop_back();
    return mk(t, "(let " + name + " = $ in $)", {lambda, use});
  }

  // (|p0, p1| body) in the current scope (it captures what it uses).
  NodeP makeLambda(const std::vector<TyP>& params, const TyP& result, int d, bool foldStep) {
    std::string f = "(|";
    size_t mark = scope_.vars.size();
    for (size_t i = 0; i < params.size(); ++i) {
      std::string pn = fresh(foldStep ? (i == 0 ? "acc" : "i") : "q");
      bool annotate = chance(0.2) && params[i]->k != K::Image;
      f += (i ? ", " : "") + pn + (annotate ? ": " + typeText(params[i]) : "");
      scope_.vars.push_back({pn, params[i]});
    }
    f += "| $)";
    if (foldStep) ++scope_.foldDepth;
    maxFoldReached_ = std::max(maxFoldReached_, scope_.foldDepth);
    NodeP body = expr(result, d);
    if (foldStep) --scope_.foldDepth;
    scope_.vars.resize(mark);
    return mk(nullptr, f, {body});
  }

  NodeP fold(const TyP& t, int d) {
    NodeP count;
    int maxCount;
    switch (uni(0, 4)) {
      case 0:
        maxCount = uni(-1, 5);
        count = mk(basicType(K::Int), intText(maxCount));
        break;
      case 1:
        count = mk(basicType(K::Int), "($ & 3)", {expr(basicType(K::Int), d - 2)});
        maxCount = 3;
        break;
      case 2:
        count = mk(basicType(K::Int), "clamp($, -1, 4)", {expr(basicType(K::Int), d - 2)});
        maxCount = 4;
        break;
      case 3:
        count = mk(basicType(K::Int), "min($, 5)", {expr(basicType(K::Int), d - 2)});
        maxCount = 5;
        break;
      default:
        count = mk(basicType(K::Int), "int(clamp($, 0.0, 4.0))", {expr(basicType(K::Float), d - 2)});
        maxCount = 4;
        break;
    }
    if (t->k == K::Float && chance(0.1)) {
      // An Int accumulator whose step gives Float becomes a Float accumulator (builtins.cpp).
      NodeP init = expr(basicType(K::Int), d - 1);
      std::string acc = fresh("acc"), i = fresh("i");
      scope_.vars.push_back({i, basicType(K::Int)});
      ++scope_.foldDepth;
      maxFoldReached_ = std::max(maxFoldReached_, scope_.foldDepth);
      NodeP body = expr(t, d - 1);
      --scope_.foldDepth;
      scope_.vars.pop_back();
      return mk(t, "fold($, $, (|" + acc + ", " + i + "| (" + acc + " + $)))", {count, init, body});
    }
    NodeP init = expr(t, d - 1);
    int saved = scope_.costMultiplier;
    scope_.costMultiplier *= std::max(1, maxCount);
    NodeP step;
    if (chance(0.3) && depthOfHelpers_ < 2) {
      // A named step function (acc, i[, k = default]).
      Helper& h = makeHelper(t, false, false, true, scope_.foldDepth + 1);
      maxFoldReached_ = std::max(maxFoldReached_, scope_.foldDepth + 1 + h.foldDepth);
      step = mk(nullptr, h.name);
      cost_ += h.cost * scope_.costMultiplier;
    } else {
      step = makeLambda({t, basicType(K::Int)}, t, d - 1, true);
    }
    scope_.costMultiplier = saved;
    return mk(t, "fold($, $, $)", {count, init, step});
  }

  // ---- helpers (module-level functions)
  std::vector<Helper*> helpersReturning(const TyP& t) {
    std::vector<Helper*> out;
    for (auto& h : helpers_)
      if (sameType(h.result, t) && scope_.foldDepth + h.foldDepth <= 2 && !h.higherOrder) out.push_back(&h);
    return out;
  }

  NodeP helperCall(const TyP& t, int d) {
    auto fits = helpersReturning(t);
    Helper* h = nullptr;
    if (!fits.empty() && chance(0.7)) h = pick(fits);
    else if (helpers_.size() < 14 && scope_.foldDepth == 0 && depthOfHelpers_ < 2) h = &makeHelper(t, chance(0.5), false);
    if (!h) return nullptr;
    return callHelper(*h, d);
  }

  NodeP hitArg(int d) {
    if (scope_.hit && chance(0.85)) return mk(hitType(), "h");
    if (scope_.hit && chance(0.5)) return mk(hitType(), "{h with uv: $}", {expr(basicType(K::Vec2), d - 1)});
    // A structural Hit: any record with Hit's fields is a Hit.
    return literal(hitType());
  }

  NodeP callHelper(const Helper& h, int d, NodeP functionArg = nullptr) {
    cost_ += h.cost * scope_.costMultiplier;
    maxFoldReached_ = std::max(maxFoldReached_, scope_.foldDepth + h.foldDepth);
    std::string f = h.name + "(";
    std::vector<NodeP> kids;
    bool first = true;
    auto sep = [&]() {
      std::string s = first ? "" : ", ";
      first = false;
      return s;
    };
    if (functionArg) {
      f += sep() + "$";
      kids.push_back(functionArg);
    }
    if (h.takesHit) {
      f += sep() + "$";
      kids.push_back(hitArg(d));
    }
    // Positional up to a point, then (for defaulted parameters) by name or left out.
    bool named = false;
    for (size_t i = 0; i < h.params.size(); ++i) {
      bool isDefault = h.firstDefault >= 0 && int(i) >= h.firstDefault;
      if (isDefault && chance(0.35)) {
        named = true;  // left out: later ones must go by name
        continue;
      }
      if (!named && isDefault && chance(0.3)) named = true;
      if (!named && !isDefault && chance(0.1) && i + 1 == h.params.size()) named = true;
      f += sep() + (named ? h.paramNames[i] + ": " : "") + "$";
      kids.push_back(h.annotated ? promotable(h.params[i], d - 1) : expr(h.params[i], d - 1));
    }
    if (!first && chance(0.08)) f += ",";  // a trailing comma
    return mk(h.result, f + ")", kids);
  }

  // A new helper returning `result`; it goes into the module before the item being generated.
  Helper& makeHelper(const TyP& result, bool takesHit, bool higherOrder, bool stepShape = false, int baseFoldDepth = 0) {
    Helper h;
    h.name = fresh("g");
    h.result = result;
    h.takesHit = takesHit && !stepShape;
    h.annotated = chance(0.5);
    h.stepShape = stepShape;
    if (stepShape) {
      h.params = {result, basicType(K::Int)};
      if (chance(0.3)) {
        h.params.push_back(basicType(K::Float));
        h.firstDefault = 2;
      }
    } else {
      int n = uni(0, 3);
      for (int i = 0; i < n; ++i) h.params.push_back(randomType(1, false));
      if (n > 0 && chance(0.3)) {
        h.firstDefault = n - 1;
        if (h.params[size_t(n - 1)]->k == K::Image || h.params[size_t(n - 1)]->k == K::Record) h.firstDefault = -1;
      }
    }
    if (higherOrder) {
      h.higherOrder = true;
      h.fparam.name = "f";
      int n = uni(1, 2);
      for (int i = 0; i < n; ++i) h.fparam.params.push_back(randomType(0, false));
      h.fparam.result = randomType(0, false);
      if (h.fparam.result->k == K::Image) h.fparam.result = basicType(K::Float);
    }
    // The body, in a scope of its own.
    Scope saved = scope_;
    int savedCost = cost_;
    int savedFold = maxFoldReached_;
    scope_ = Scope{};
    scope_.hit = h.takesHit;
    scope_.foldDepth = baseFoldDepth;
    maxFoldReached_ = baseFoldDepth;
    ++depthOfHelpers_;
    std::string f = "fn " + h.name + "(";
    bool first = true;
    auto sep = [&]() {
      std::string s = first ? "" : ", ";
      first = false;
      return s;
    };
    if (h.higherOrder) {
      f += sep() + "f";
      if (chance(0.4)) {
        std::string sig = "(";
        for (size_t i = 0; i < h.fparam.params.size(); ++i) sig += (i ? ", " : "") + typeText(h.fparam.params[i]);
        sig += ") -> " + typeText(h.fparam.result);
        if (chance(0.4)) {
          // A type alias of the function type.
          std::string alias = "F" + std::to_string(counter_++);
          auto item = mk(nullptr, "type " + alias + " = " + sig + "\n");
          item->reducible = false;
          item->defines = alias;
          pending_.push_back(item);
          sig = alias;
        }
        f += ": " + sig;
      }
      scope_.callables.push_back(h.fparam);
    }
    if (h.takesHit) f += sep() + (h.annotated || chance(0.5) ? "h: Hit" : "h");
    std::vector<NodeP> kids;
    for (size_t i = 0; i < h.params.size(); ++i) {
      std::string pn = stepShape ? (i == 0 ? "acc" : i == 1 ? "i" : "k") + std::to_string(counter_++) : fresh("x");
      h.paramNames.push_back(pn);
      f += sep() + pn;
      if (h.annotated) f += ": " + typeText(h.params[i]);
      if (h.firstDefault >= 0 && int(i) >= h.firstDefault) {
        f += " = $";
        kids.push_back(literal(h.params[i]));
      }
      scope_.vars.push_back({pn, h.params[i]});
    }
    f += ")";
    if (h.annotated) f += " -> " + typeText(result);
    cost_ = 0;
    NodeP body;
    if (chance(0.3)) {
      body = block(result, options_.maxDepth - 1);
      f += " $\n";
    } else {
      body = expr(result, options_.maxDepth - 1);
      f += " = $\n";
    }
    kids.push_back(body);
    h.cost = std::max(1, cost_);
    h.foldDepth = maxFoldReached_ - baseFoldDepth;
    maxFoldReached_ = savedFold;
    cost_ = savedCost;
    --depthOfHelpers_;
    scope_ = saved;
    auto item = mk(nullptr, f, kids);
    item->reducible = false;
    item->defines = h.name;
    pending_.push_back(item);
    helpers_.push_back(h);
    return helpers_.back();
  }

  // A call of a higher-order helper with a lambda, a named function or a std function.
  NodeP higherOrderCall(const TyP& t, int d) {
    if (scope_.foldDepth > 0) return nullptr;
    Helper* h = nullptr;
    std::vector<Helper*> fits;
    for (auto& x : helpers_)
      if (x.higherOrder && sameType(x.result, t)) fits.push_back(&x);
    if (!fits.empty() && chance(0.6)) h = pick(fits);
    else if (helpers_.size() < 14 && depthOfHelpers_ < 2) h = &makeHelper(t, false, true);
    if (!h) return nullptr;
    const Callable& sig = h->fparam;
    NodeP farg;
    // A named helper of exactly that signature?
    std::vector<Helper*> named;
    for (auto& x : helpers_) {
      if (x.higherOrder || x.takesHit || x.name == h->name || !sameType(x.result, sig.result)) continue;
      size_t required = x.firstDefault >= 0 ? size_t(x.firstDefault) : x.params.size();
      if (sig.params.size() < required || sig.params.size() > x.params.size()) continue;
      bool ok = true;
      for (size_t i = 0; i < sig.params.size(); ++i) ok = ok && sameType(x.params[i], sig.params[i]);
      if (ok) named.push_back(&x);
    }
    if (!named.empty() && chance(0.4)) {
      farg = mk(nullptr, pick(named)->name);
    } else if (sig.params.size() == 1 && sig.params[0]->k == K::Float && sig.result->k == K::Float && chance(0.2)) {
      farg = mk(nullptr, exactOnly_ ? pick(std::vector<std::string>{"floor", "abs", "fract", "sqrt"})
                                    : pick(std::vector<std::string>{"floor", "abs", "fract", "sqrt", "sin", "exp2"}));
    } else {
      farg = makeLambda(sig.params, sig.result, d - 1, false);
    }
    return callHelper(*h, d, farg);
  }

  // ---- constants and entries
  void makeConstant() {
    TyP t = randomType(1, false);
    if (t->k == K::Image) t = basicType(K::Float);
    std::string name = fresh("c");
    Scope saved = scope_;
    scope_ = Scope{};
    std::string annotation = chance(0.3) ? ": " + typeText(t) : "";
    NodeP value = annotation.empty() ? expr(t, 3) : promotable(t, 3);
    scope_ = saved;
    flushPending();
    auto item = mk(nullptr, "let " + name + annotation + " = $\n", {value});
    item->reducible = false;
    item->defines = name;
    items_.push_back(item);
    globals_.push_back({name, t});
  }

  void makeEntry(int index) {
    Entry e;
    e.name = "e" + std::to_string(index);
    int w = weighted({30, 12, 6, 6, 8, 4, 8, 10, 6, 6});
    static const K kinds[] = {K::Float, K::Int, K::Bool, K::Vec2, K::Vec3, K::Vec4, K::Color, K::Spectrum, K::Record, K::Material};
    e.result = kinds[w] == K::Record ? randomRecord(1, nullptr) : basicType(kinds[w]);
    if (e.result->k == K::Record)  // no images in results: handles are process-specific but agree; keep it simple
      for (auto& f : e.result->fields)
        if (containsKind(f.second, K::Image)) e.result = basicType(K::Float);
    int extra = weighted({4, 3, 2, 1});
    scope_ = Scope{};
    scope_.hit = true;
    std::string f = "export fn " + e.name + "(h: Hit";
    for (int i = 0; i < extra; ++i) {
      static const K pk[] = {K::Float, K::Int, K::Bool, K::Vec3, K::Color, K::Spectrum, K::Vec2};
      TyP t = basicType(pk[uni(0, 6)]);
      if (chance(0.1)) {
        // A record argument: its fields are passed in name order (docs/abi.md, word layout).
        t = randomRecord(1, nullptr);
        if (containsKind(t, K::Material) || containsKind(t, K::Image)) t = recordType({{"a", basicType(K::Float)}, {"b", basicType(K::Int)}});
      }
      std::string pn = fresh("x");
      f += ", " + pn + ": " + typeText(t);
      e.params.push_back(t);
      scope_.vars.push_back({pn, t});
    }
    f += ") -> " + typeText(e.result);
    cost_ = 0;
    NodeP body;
    if (chance(0.3)) {
      body = block(e.result, options_.maxDepth);
      f += " $\n";
    } else {
      body = expr(e.result, options_.maxDepth);
      f += " = $\n";
    }
    flushPending();
    auto item = mk(nullptr, f, {body});
    item->reducible = false;
    item->entry = e.name;
    items_.push_back(item);
    program_.entries.push_back(e);
  }

  void flushPending() {
    for (auto& p : pending_) items_.push_back(p);
    pending_.clear();
  }

  // ---- type-specific productions
  NodeP unaryBuiltin(const TyP& t, int d, bool exactOnly = false) {
    static const std::vector<std::string> exact = {"sign", "floor", "ceil", "trunc", "round", "fract", "sqrt", "abs"};
    static const std::vector<std::string> inexact = {"exp",  "exp2", "log",  "log2", "sin",  "cos",  "tan",
                                                     "asin", "acos", "atan", "sinh", "cosh", "tanh"};
    const std::string& name = (exactOnly || exactOnly_ || chance(0.6)) ? pick(exact) : pick(inexact);
    NodeP arg = (t->k == K::Float && chance(0.1)) ? expr(basicType(K::Int), d - 1) : expr(t, d - 1);
    if (name == "abs" && arg->type->k == K::Int) arg = expr(t, d - 1);
    NodeP n = mk(t, name + "($)", {arg});
    n->transcendental = std::find(inexact.begin(), inexact.end(), name) != inexact.end();
    return n;
  }

  // An operand of arithmetic producing t: t itself, or a scalar broadcast (section 3).
  NodeP operand(const TyP& t, int d) {
    if (t->k != K::Float && t->k != K::Int && chance(0.25)) return expr(chance(0.8) ? basicType(K::Float) : basicType(K::Int), d);
    if (t->k == K::Float && chance(0.12)) return expr(basicType(K::Int), d);
    return expr(t, d);
  }

  NodeP arith(const TyP& t, int d) {
    static const std::vector<std::string> ops = {"+", "-", "*", "/", "%", "+", "*", "-"};
    const std::string& op = pick(ops);
    NodeP a = operand(t, d - 1), b = operand(t, d - 1);
    // A Float-based result needs at least one operand of its type (Int op Int is Int).
    if (t->k != K::Int && !sameType(a->type, t) && !sameType(b->type, t)) b = expr(t, d - 1);
    return mk(t, "($ " + op + " $)", {a, b});
  }

  // Float-based lane-wise builtins of two or three arguments.
  NodeP laneBuiltin(const TyP& t, int d) {
    auto arg = [&]() { return (t->k == K::Float && chance(0.1)) ? expr(basicType(K::Int), d - 1) : expr(t, d - 1); };
    auto scalarOr = [&]() { return (t->k != K::Float && chance(0.3)) ? expr(basicType(K::Float), d - 1) : expr(t, d - 1); };
    int which = uni(0, 8);
    if (exactOnly_ && (which == 2 || which == 8)) which = uni(3, 7);
    switch (which) {
      case 0:
      case 1: {
        NodeP a = arg(), b = arg();
        if (!sameType(a->type, t) && !sameType(b->type, t)) b = expr(t, d - 1);  // min(Int, Int) is an Int
        return mk(t, std::string(uni(0, 1) ? "min" : "max") + "($, $)", {a, b});
      }
      case 2: {
        NodeP n = mk(t, "pow($, $)", {expr(t, d - 1), expr(t, d - 1)});
        n->transcendental = true;
        return n;
      }
      case 3: return mk(t, "mod($, $)", {expr(t, d - 1), t->k == K::Float ? arg() : scalarOr()});
      case 4: return mk(t, "step($, $)", {scalarOr(), expr(t, d - 1)});
      case 5: {
        if (t->k != K::Float && chance(0.5)) {
          NodeP x = expr(t, d - 1), lo = expr(basicType(K::Float), d - 1), hi = expr(basicType(K::Float), d - 1);
          return mk(t, "clamp($, $, $)", {x, lo, hi});
        }
        return mk(t, "clamp($, $, $)", {expr(t, d - 1), expr(t, d - 1), expr(t, d - 1)});
      }
      case 6: return mk(t, "mix($, $, $)", {expr(t, d - 1), expr(t, d - 1), scalarOr()});
      case 7: {
        if (t->k != K::Float && chance(0.5)) {
          NodeP e0 = expr(basicType(K::Float), d - 1), e1 = expr(basicType(K::Float), d - 1), x = expr(t, d - 1);
          return mk(t, "smoothstep($, $, $)", {e0, e1, x});
        }
        return mk(t, "smoothstep($, $, $)", {expr(t, d - 1), expr(t, d - 1), expr(t, d - 1)});
      }
      default: {
        NodeP n = mk(t, "atan2($, $)", {expr(t, d - 1), expr(t, d - 1)});
        n->transcendental = true;
        return n;
      }
    }
  }

  NodeP stdCall(const TyP& t, int d) {
    std::vector<const StdFn*> fits;
    for (auto& s : stdFns()) {
      if (!sameType(codeType(s.result), t)) continue;
      if (cost_ + s.cost * scope_.costMultiplier > 250) continue;
      if (scope_.foldDepth > 0 && s.cost >= 16) continue;
      if (exactOnly_ && s.transcendental) continue;
      fits.push_back(&s);
    }
    if (fits.empty()) return nullptr;
    const StdFn& s = *pick(fits);
    cost_ += s.cost * scope_.costMultiplier;
    std::string f = stdName(s.module, s.name) + "(";
    std::vector<NodeP> kids;
    bool named = false, first = true;
    for (const StdParam& p : parseParams(s.params)) {
      if (p.optional && chance(0.4)) {
        named = true;
        continue;
      }
      if (!named && p.optional && chance(0.3)) named = true;
      f += (first ? "" : ", ") + (named ? p.name + ": " : "") + "$";
      first = false;
      if (p.code == 'I' && p.name == "octaves") {
        kids.push_back(chance(0.6) ? mk(basicType(K::Int), std::to_string(uni(0, 4)))
                                   : mk(basicType(K::Int), "($ & 3)", {expr(basicType(K::Int), d - 2)}));
      } else if (p.code == 'f' || p.code == 'g') {
        kids.push_back(noiseFunction(p.code == 'f' ? basicType(K::Vec3) : basicType(K::Vec2), d));
      } else if (p.code == 'H') {
        kids.push_back(hitArg(d));
      } else {
        kids.push_back(promotable(codeType(p.code), d - 1));
      }
    }
    NodeP n = mk(t, f + ")", kids);
    n->transcendental = s.transcendental;
    return n;
  }

  // A (VecN) -> Float function value for fbm & co.
  NodeP noiseFunction(const TyP& v, int d) {
    bool three = v->k == K::Vec3;
    switch (uni(0, 2)) {
      case 0: {
        static const std::vector<std::string> n3 = {"perlin", "simplex", "value_noise", "worley", "worley_edge"};
        static const std::vector<std::string> n2 = {"perlin2", "simplex2", "value_noise2", "worley2", "worley_edge2"};
        return mk(nullptr, stdName("noise", three ? pick(n3) : pick(n2)));
      }
      case 1: {
        for (auto& h : helpers_)
          if (!h.higherOrder && !h.takesHit && h.result->k == K::Float && !h.params.empty() && sameType(h.params[0], v) &&
              (h.params.size() == 1 || h.firstDefault == 1))
            return mk(nullptr, h.name);
        [[fallthrough]];
      }
      default: {
        int saved = scope_.costMultiplier;
        scope_.costMultiplier *= 4;
        ++scope_.foldDepth;  // fbm loops over it
        NodeP l = makeLambda({v}, basicType(K::Float), std::max(1, d - 2), false);
        --scope_.foldDepth;
        scope_.costMultiplier = saved;
        return l;
      }
    }
  }

  NodeP swizzleFrom(const TyP& t, int d) {
    // From a vector or Color to t (Float or VecN).
    int want = fixedLanes(t);
    int w = weighted({3, 4, 2, 3});
    TyP src = basicType(w == 0 ? K::Vec2 : w == 1 ? K::Vec3 : w == 2 ? K::Vec4 : K::Color);
    int n = fixedLanes(src);
    const char* letters = src->k == K::Color ? "rgb" : "xyzw";
    if (src->k == K::Color && want == 4 && chance(0.5)) src = basicType(K::Vec4), letters = "xyzw", n = 4;
    std::string s;
    for (int i = 0; i < want; ++i) s += letters[uni(0, n - 1)];
    return mk(t, "($)." + s, {expr(src, d - 1)});
  }

  NodeP imageLookup(const TyP& t, int d) {
    if (options_.imageDir.empty()) return nullptr;
    NodeP img = expr(basicType(K::Image), d - 1);
    NodeP uv = expr(basicType(K::Vec2), d - 1);
    std::string wrap = chance(0.5) ? "" : chance(0.5) ? ", wrap_mirror" : ", wrap_clamp";
    if (t->k == K::Float) return mk(t, "sample_alpha($, $" + wrap + ")", {img, uv});
    if (t->k == K::Vec2) return mk(t, "image_size($)", {img});
    if (t->k != K::Color) return nullptr;
    switch (uni(0, 3)) {
      case 0: return mk(t, "sample($, $" + wrap + ")", {img, uv});
      case 1: return mk(t, "sample_nearest($, $" + wrap + ")", {img, uv});
      case 2: return mk(t, "sample_filtered($, $" + wrap + ")", {img, hitArg(d)});
      default:
        return mk(t, "sample_filtered($, $, $, $" + wrap + ")",
                  {img, uv, expr(basicType(K::Vec2), d - 1), expr(basicType(K::Vec2), d - 1)});
    }
  }

  // An Int narrowed to a few values (`x & 15`, `(x >> 4) & 7`, a non-negative `x % 12`) and a
  // chain of ifs over it whose arms depend only on it: what O1 turns into constant tables
  // (compiler/small_domain_tables.cpp), sign choices (select lowering) included.
  NodeP smallDomainSelect(const TyP& t, int d) {
    TyP i = basicType(K::Int);
    NodeP source = chance(0.5) ? hitInt(d - 1) : expr(i, d - 2);
    NodeP narrowed;
    switch (uni(0, 5)) {
      case 0: narrowed = mk(i, "($ & " + pick(std::vector<std::string>{"1", "3", "7", "15", "31", "63", "12", "240"}) + ")", {source}); break;
      case 1: narrowed = mk(i, "(($ >> " + std::to_string(uni(0, 28)) + ") & " + pick(std::vector<std::string>{"3", "7", "15"}) + ")", {source}); break;
      case 2: narrowed = mk(i, "(($ & 2147483647) % " + pick(std::vector<std::string>{"3", "5", "6", "12", "16", "17", "64"}) + ")", {source}); break;
      case 3: narrowed = mk(i, "(($ & 255) % " + pick(std::vector<std::string>{"3", "12", "7"}) + ")", {source}); break;
      case 4: narrowed = mk(i, "($ % 12)", {source}); break;
      default: narrowed = mk(i, "((($ >> 8) & 15) | 16)", {source}); break;
    }
    std::string g = fresh("k");
    scope_.vars.push_back({g, i});
    auto cond = [&]() -> std::string {
      switch (uni(0, 5)) {
        case 0: return "(" + g + " < " + std::to_string(uni(0, 16)) + ")";
        case 1: return "(" + g + " == " + std::to_string(uni(0, 16)) + ")";
        case 2: return "((" + g + " & " + std::to_string(1 << uni(0, 3)) + ") == 0)";
        case 3: return "((" + g + " > " + std::to_string(uni(0, 8)) + ") && (" + g + " != " + std::to_string(uni(0, 16)) + "))";
        case 4: return "((" + g + " == " + std::to_string(uni(0, 16)) + ") || (" + g + " == " + std::to_string(uni(0, 16)) + "))";
        default: return "(" + g + " >= " + std::to_string(uni(0, 12)) + ")";
      }
    };
    NodeP shared = chance(0.5) ? expr(t, d - 2) : nullptr;  // a value chosen with its sign
    auto arm = [&]() -> NodeP {
      std::string c = std::to_string(uni(-3, 9));
      if (t->k == K::Int) {
        switch (uni(0, 7)) {
          case 0: return mk(t, "(" + g + " * " + c + ")");
          case 1: return mk(t, "(100 - " + g + ")");
          case 2: return mk(t, "(" + g + " / (" + g + " - " + std::to_string(uni(0, 4)) + "))");
          case 3: return mk(t, "(" + g + " % (" + g + " - " + std::to_string(uni(0, 4)) + "))");
          case 4: return mk(t, "(1 << " + g + ")");
          case 5: return mk(t, "((-2147483648) / (" + g + " - 1))");
          case 6: return mk(t, "(-" + g + ")");
          default: return mk(t, intText(randomInt(rng_)));
        }
      }
      switch (uni(0, 10)) {
        case 0: return mk(t, "(float(" + g + ") * " + floatText(randomFloat(rng_)) + ")");
        case 1: return mk(t, "(-1.0 / float(" + g + "))");
        case 2: return mk(t, "float(" + g + " - " + c + ")");
        case 3: return mk(t, floatText(randomFloat(rng_)));
        case 4: return mk(t, "(if ((" + g + " & 1) == 0) { 1.0 } else { -1.0 })");
        case 5: return mk(t, "(float(" + g + " * " + g + ") / 7.0)");
        case 6: return mk(t, "(float(" + g + ") % 3.0)");
        case 7: return mk(t, "(0.0 / float(" + g + "))");
        case 8: return mk(t, "(" + floatText(randomFloat(rng_)) + " * float(" + g + "))");
        case 9:
          if (shared) return mk(t, "(if ((" + g + " & 2) == 0) { $ } else { (-$) })", {shared, shared});
          [[fallthrough]];
        default: return mk(t, "(float(" + g + ") - 0.5)");
      }
    };
    NodeP chain;
    int arms = uni(2, 4);
    std::string f = "(if " + cond() + " { $ }";
    std::vector<NodeP> kids = {arm()};
    for (int k = 2; k < arms; ++k) {
      f += " else if " + cond() + " { $ }";
      kids.push_back(arm());
    }
    f += " else { $ })";
    kids.push_back(arm());
    chain = mk(t, f, kids);
    scope_.vars.pop_back();
    // Combined with something else, so that the chain is the largest computation of the leaf.
    NodeP use = t->k == K::Int ? mk(t, "($ + $)", {chain, expr(t, d - 2)}) : mk(t, "($ * $)", {chain, expr(t, d - 2)});
    return mk(t, "(let " + g + " = $ in $)", {narrowed, use});
  }

  // An Int that varies with the hit: a scaled coordinate, or a hash of one.
  NodeP hitInt(int d) {
    TyP i = basicType(K::Int);
    NodeP x = expr(basicType(K::Float), std::max(0, d - 1));
    switch (uni(0, 3)) {
      case 0: return mk(i, "int(($ * 4096.0))", {x});
      case 1: return mk(i, "int(floor(($ * 16.0)))", {x});
      case 2: return mk(i, stdName("math", "hash") + "(int(($ * 65536.0)))", {x});
      default: return mk(i, "(int(($ * 1000.0)) * 747796405)", {x});
    }
  }

  NodeP floatExpr(int d) {
    TyP t = basicType(K::Float);
    for (int attempt = 0; attempt < 4; ++attempt) {
      NodeP n;
      switch (weighted({10, 2, 6, 5, 3, 2, 2, 1.5, 3, 1.5, 4, 0.5, 0.3, 2, 0.7})) {
        case 0: n = arith(t, d); break;
        case 1: n = mk(t, "(-$)", {expr(t, d - 1)}); break;
        case 2: n = unaryBuiltin(t, d); break;
        case 3: n = laneBuiltin(t, d); break;
        case 4: {
          TyP v = basicType(pick(std::vector<K>{K::Vec2, K::Vec3, K::Vec4, K::Color}));
          switch (uni(0, 2)) {
            case 0: n = mk(t, "dot($, $)", {expr(v, d - 1), expr(v, d - 1)}); break;
            case 1: n = mk(t, "length($)", {expr(v, d - 1)}); break;
            default: n = mk(t, "distance($, $)", {expr(v, d - 1), expr(v, d - 1)}); break;
          }
          break;
        }
        case 5: n = mk(t, "luminance($)", {expr(basicType(K::Color), d - 1)}); break;
        case 6: n = mk(t, "float($)", {expr(basicType(K::Int), d - 1)}); break;
        case 7: n = hitField(t); break;
        case 8: n = swizzleFrom(t, d); break;
        case 9: n = mk(t, "fract($)", {expr(t, d - 1)}); break;
        case 10: n = stdCall(t, d); break;
        case 11: n = imageLookup(t, d); break;
        case 12: n = mk(t, pick(std::vector<std::string>{"pi", "tau", "inf", "nan"})); break;
        case 13: n = smallDomainSelect(t, d); break;
        default: {
          // Signed zeros.
          static const std::vector<std::string> zeros = {"(-0.0)", "(0.0 * (-1.0))", "min((-0.0), 0.0)", "max((-0.0), 0.0)",
                                                         "sign((-0.0))", "((-0.0) + (-0.0))", "(0.0 - 0.0)", "abs((-0.0))"};
          n = chance(0.5) ? mk(t, pick(zeros)) : mk(t, "($ * 0.0)", {expr(t, d - 1)});
          break;
        }
      }
      if (n) return n;
    }
    return leaf(t);
  }

  NodeP intExpr(int d) {
    TyP t = basicType(K::Int);
    static const std::vector<std::string> ops = {"+", "-", "*", "/", "%", "&", "|", "^", "<<", ">>"};
    for (int attempt = 0; attempt < 4; ++attempt) {
      NodeP n;
      switch (weighted({12, 2, 2, 4, 4, 3, 0.5, 1.5, 1.5})) {
        case 0: n = mk(t, "($ " + pick(ops) + " $)", {expr(t, d - 1), expr(t, d - 1)}); break;
        case 1: n = mk(t, "(-$)", {expr(t, d - 1)}); break;
        case 2: n = mk(t, "(~$)", {expr(t, d - 1)}); break;
        case 3:
          switch (uni(0, 3)) {
            case 0: n = mk(t, "abs($)", {expr(t, d - 1)}); break;
            case 1: n = mk(t, "min($, $)", {expr(t, d - 1), expr(t, d - 1)}); break;
            case 2: n = mk(t, "max($, $)", {expr(t, d - 1), expr(t, d - 1)}); break;
            default: n = mk(t, "clamp($, $, $)", {expr(t, d - 1), expr(t, d - 1), expr(t, d - 1)}); break;
          }
          break;
        case 4: n = mk(t, "int($)", {expr(chance(0.85) ? basicType(K::Float) : t, d - 1)}); break;
        case 5: n = stdCall(t, d); break;
        case 6: n = mk(t, pick(std::vector<std::string>{"wrap_repeat", "wrap_clamp", "wrap_mirror"})); break;
        case 7: n = smallDomainSelect(t, d); break;
        default: n = hitInt(d); break;
      }
      if (n) return n;
    }
    return leaf(t);
  }

  NodeP boolExpr(int d) {
    TyP t = basicType(K::Bool);
    static const std::vector<std::string> cmp = {"<", "<=", ">", ">="};
    switch (weighted({6, 4, 4, 2, 3, 2, 1})) {
      case 0: {
        // Float comparison (an Int operand is promoted).
        NodeP a = expr(chance(0.15) ? basicType(K::Int) : basicType(K::Float), d - 1);
        NodeP b = expr(basicType(K::Float), d - 1);
        if (chance(0.5)) std::swap(a, b);
        return mk(t, "($ " + pick(cmp) + " $)", {a, b});
      }
      case 1: return mk(t, "($ " + pick(cmp) + " $)", {expr(basicType(K::Int), d - 1), expr(basicType(K::Int), d - 1)});
      case 2: {
        TyP e = basicType(pick(std::vector<K>{K::Bool, K::Int, K::Float, K::Float, K::Vec2, K::Vec3, K::Vec4, K::Color}));
        return mk(t, std::string("($ ") + (chance(0.5) ? "==" : "!=") + " $)", {expr(e, d - 1), expr(e, d - 1)});
      }
      case 3: return mk(t, "(!$)", {expr(t, d - 1)});
      case 4: return mk(t, std::string("($ ") + (chance(0.5) ? "&&" : "||") + " $)", {expr(t, d - 1), expr(t, d - 1)});
      case 5: return mk(t, std::string(chance(0.5) ? "is_nan" : "is_inf") + "($)",
                        {expr(chance(0.1) ? basicType(K::Int) : basicType(K::Float), d - 1)});
      default: return leaf(t);
    }
  }

  NodeP vecExpr(const TyP& t, int d) {
    int n = fixedLanes(t);
    std::string ctor = "vec" + std::to_string(n);
    for (int attempt = 0; attempt < 4; ++attempt) {
      NodeP r;
      switch (weighted({8, 1.5, 4, 4, 2, 4, 3, 2, 2, 3, 0.5})) {
        case 0: r = arith(t, d); break;
        case 1: r = mk(t, "(-$)", {expr(t, d - 1)}); break;
        case 2: r = unaryBuiltin(t, d); break;
        case 3: r = laneBuiltin(t, d); break;
        case 4: r = mk(t, "normalize($)", {expr(t, d - 1)}); break;
        case 5: {
          // Constructor: a splat, or parts whose sizes add up to n.
          if (chance(0.25)) {
            r = mk(t, ctor + "($)", {expr(chance(0.8) ? basicType(K::Float) : basicType(K::Int), d - 1)});
            break;
          }
          std::string f = ctor + "(";
          std::vector<NodeP> kids;
          int left = n;
          while (left > 0) {
            int take = std::min(left, uni(1, 3));
            if (take == 1 && chance(0.1)) kids.push_back(expr(basicType(K::Int), d - 1));
            else kids.push_back(expr(take == 1 ? basicType(K::Float) : basicType(take == 2 ? K::Vec2 : K::Vec3), d - 1));
            f += kids.size() > 1 ? ", $" : "$";
            left -= take;
          }
          r = mk(t, f + ")", kids);
          break;
        }
        case 6: r = swizzleFrom(t, d); break;
        case 7: r = hitField(t); break;
        case 8:
          if (n == 3) r = chance(0.5) ? mk(t, "cross($, $)", {expr(t, d - 1), expr(t, d - 1)})
                                      : mk(t, "vec3($)", {expr(basicType(K::Color), d - 1)});
          break;
        case 9: r = stdCall(t, d); break;
        default: r = imageLookup(t, d); break;
      }
      if (r) return r;
    }
    return leaf(t);
  }

  NodeP colorExpr(int d) {
    TyP t = basicType(K::Color);
    for (int attempt = 0; attempt < 4; ++attempt) {
      NodeP r;
      switch (weighted({8, 1, 3, 3, 4, 2, 2, 4, 1})) {
        case 0: r = arith(t, d); break;
        case 1: r = mk(t, "(-$)", {expr(t, d - 1)}); break;
        case 2: r = unaryBuiltin(t, d); break;
        case 3: r = laneBuiltin(t, d); break;
        case 4: r = mk(t, "rgb($, $, $)", {expr(basicType(K::Float), d - 1), expr(basicType(K::Float), d - 1), expr(basicType(K::Float), d - 1)}); break;
        case 5: r = mk(t, "rgb($)", {expr(chance(0.8) ? basicType(K::Float) : basicType(K::Int), d - 1)}); break;
        case 6: r = mk(t, "color($)", {expr(basicType(K::Vec3), d - 1)}); break;
        case 7: r = stdCall(t, d); break;
        default: r = imageLookup(t, d); break;
      }
      if (r) return r;
    }
    return leaf(t);
  }

  NodeP spectrumExpr(int d) {
    TyP t = basicType(K::Spectrum);
    for (int attempt = 0; attempt < 4; ++attempt) {
      NodeP r;
      switch (weighted({8, 1, 3, 3, 2, 2, 1.5, 3})) {
        case 0: r = arith(t, d); break;
        case 1: r = mk(t, "(-$)", {expr(t, d - 1)}); break;
        case 2: r = unaryBuiltin(t, d); break;
        case 3: r = laneBuiltin(t, d); break;
        case 4: r = mk(t, "lambda_nm"); break;
        case 5: r = mk(t, "spectrum($)", {expr(chance(0.85) ? basicType(K::Float) : basicType(K::Int), d - 1)}); break;
        case 6:
          r = mk(t, pick(std::vector<std::string>{"reflectance_spectrum", "unbounded_spectrum", "illuminant_spectrum"}) + "($)",
                 {expr(basicType(K::Color), d - 1)});
          break;
        default: r = stdCall(t, d); break;
      }
      if (r) return r;
    }
    return leaf(t);
  }

  NodeP recordExpr(const TyP& t, int d) {
    double r = real();
    if (r < 0.45) {
      std::string f = "{";
      std::vector<NodeP> kids;
      auto fields = t->fields;
      std::shuffle(fields.begin(), fields.end(), rng_);
      for (size_t i = 0; i < fields.size(); ++i) {
        f += (i ? ", " : "") + fields[i].first + ": $";
        kids.push_back(expr(fields[i].second, d - 1));
      }
      return mk(t, f + (chance(0.1) ? ",}" : "}"), kids);
    }
    if (r < 0.75) {
      // {base with f: e, ...}
      auto fields = t->fields;
      std::shuffle(fields.begin(), fields.end(), rng_);
      int n = uni(1, int(fields.size()));
      std::string f = "{$ with ";
      std::vector<NodeP> kids = {expr(t, d - 1)};
      for (int i = 0; i < n; ++i) {
        f += (i ? ", " : "") + fields[size_t(i)].first + ": $";
        kids.push_back(expr(fields[size_t(i)].second, d - 1));
      }
      return mk(t, f + "}", kids);
    }
    if (NodeP s = stdCall(t, d)) return s;
    return leaf(t);
  }

  NodeP colorOrSpectrum(int d) {
    switch (uni(0, 3)) {
      case 0: return expr(basicType(K::Color), d - 1);
      case 1: return expr(basicType(K::Spectrum), d - 1);
      case 2: return expr(basicType(K::Float), d - 1);
      default: return literal(basicType(K::Color));
    }
  }
  NodeP floatOrSpectrum(int d) { return chance(0.5) ? expr(basicType(K::Float), d - 1) : expr(basicType(K::Spectrum), d - 1); }

  NodeP materialExpr(int d) {
    TyP t = basicType(K::Material);
    TyP f = basicType(K::Float);
    switch (weighted({4, 2, 3, 2, 1.5, 1.5, 1, 1, 2, 2, 2, 2.5, 3})) {
      case 0: return mk(t, "diffuse($)", {colorOrSpectrum(d)});
      case 1: return mk(t, "emission($)", {colorOrSpectrum(d)});
      case 2:
        if (chance(0.3)) return mk(t, "dielectric($)", {floatOrSpectrum(d)});
        if (chance(0.3)) return mk(t, "dielectric(roughness: $, ior: $)", {expr(f, d - 1), floatOrSpectrum(d)});
        return mk(t, "dielectric($, $)", {floatOrSpectrum(d), expr(f, d - 1)});
      case 3:
        if (chance(0.3)) return mk(t, "conductor($, $)", {colorOrSpectrum(d), colorOrSpectrum(d)});
        if (chance(0.3)) return mk(t, "conductor($, k: $, roughness: $)", {colorOrSpectrum(d), colorOrSpectrum(d), expr(f, d - 1)});
        return mk(t, "conductor($, $, $)", {colorOrSpectrum(d), colorOrSpectrum(d), expr(f, d - 1)});
      case 4:
        if (chance(0.3)) return mk(t, "thin_dielectric($)", {floatOrSpectrum(d)});
        if (chance(0.3)) return mk(t, "thin_dielectric($, transmission_tint: $)", {floatOrSpectrum(d), colorOrSpectrum(d)});
        return mk(t, "thin_dielectric($, $, $)", {floatOrSpectrum(d), expr(f, d - 1), colorOrSpectrum(d)});
      case 5: return mk(t, "glossy($, $)", {colorOrSpectrum(d), expr(f, d - 1)});
      case 6: return mk(t, "glossy_dielectric($, $)", {floatOrSpectrum(d), expr(f, d - 1)});
      case 7: return mk(t, "sheen($, $)", {colorOrSpectrum(d), expr(f, d - 1)});
      case 8:
        if (chance(0.3)) return mk(t, "layer(base: $, coat: $)", {expr(t, d - 1), expr(t, d - 1)});
        return mk(t, "layer($, $)", {expr(t, d - 1), expr(t, d - 1)});
      case 9: return mk(t, "add_material($, $)", {expr(t, d - 1), expr(t, d - 1)});
      case 10: return mk(t, "scale_material($, $)", {expr(t, d - 1), colorOrSpectrum(d)});
      case 11: return mk(t, "mix_material($, $, $)", {expr(t, d - 1), expr(t, d - 1), expr(f, d - 1)});
      default:
        if (NodeP s = stdCall(t, d)) return s;
        return mk(t, "diffuse($)", {colorOrSpectrum(d)});
    }
  }

  std::mt19937_64 rng_;
  GenOptions options_;
  Program program_;
  Scope scope_;
  std::vector<Var> globals_;
  std::deque<Helper> helpers_;  // a deque: references stay valid while helpers are added
  std::vector<NodeP> items_, pending_;
  std::map<std::string, int> importStyle_;
  std::map<std::string, std::set<std::string>> imported_;
  int counter_ = 0;
  int cost_ = 0;
  int depthOfHelpers_ = 0;
  int maxFoldReached_ = 0;  // the deepest fold nesting reached in the body being generated
  bool exactOnly_ = false;  // no transcendental builtins (docs/abi.md: compared bit for bit)
  int factories_ = 0;
};

}  // namespace

Program generate(uint64_t seed, const GenOptions& options) { return Gen(seed, options).run(); }

static NodeP deepCopy(const NodeP& n) {
  auto c = std::make_shared<Node>(*n);
  for (auto& k : c->kids) k = deepCopy(k);
  return c;
}

static void wrapArguments(const NodeP& n, const std::string& zero) {
  for (auto& k : n->kids) wrapArguments(k, zero);
  if (!n->transcendental) return;
  for (auto& k : n->kids)
    if (k->type && isFloatBased(k->type)) k = mk(k->type, "($ + " + zero + ")", {k});
}

Program withOpaqueTranscendentalArguments(const Program& p, const std::string& zero) {
  Program q = p;
  for (auto& item : q.items) {
    item = deepCopy(item);
    wrapArguments(item, zero);
  }
  return q;
}

// ---- entry arguments -----------------------------------------------------------------------

ArgValue randomArg(const TyP& t, uint64_t seed) {
  std::mt19937_64 rng(seed * 0xD1B54A32D192ED03ull + 7);
  auto f = [&]() {
    // Mostly ordinary values, sometimes edge values.
    if (std::uniform_int_distribution<int>(0, 9)(rng) < 7) return float(std::uniform_real_distribution<double>(-4, 4)(rng));
    return randomFloat(rng);
  };
  ArgValue v;
  v.k = t->k;
  switch (t->k) {
    case K::Bool: v.i = int32_t(rng() & 1); break;
    case K::Int: v.i = randomInt(rng); break;
    case K::Spectrum:
      for (float& x : v.spectrum) x = f();
      break;
    case K::Record:
      for (size_t i = 0; i < t->fields.size(); ++i) v.fields.push_back({t->fields[i].first, randomArg(t->fields[i].second, rng())});
      break;
    default:
      for (int i = 0; i < fixedLanes(t); ++i) v.f[i] = f();
      break;
  }
  return v;
}

std::string describeArg(const TyP& t, const ArgValue& v) {
  auto fl = [](float x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", double(x));
    return std::string(buf);
  };
  switch (t->k) {
    case K::Bool: return v.i ? "true" : "false";
    case K::Int: return std::to_string(v.i);
    case K::Spectrum: {
      std::string s = "spectrum lanes(";
      for (int i = 0; i < 8; ++i) s += (i ? ", " : "") + fl(v.spectrum[i]);
      return s + ")";
    }
    case K::Record: {
      std::string s = "{";
      for (size_t i = 0; i < t->fields.size(); ++i)
        s += (i ? ", " : "") + t->fields[i].first + ": " + describeArg(t->fields[i].second, v.fields[i].second);
      return s + "}";
    }
    default: {
      int n = fixedLanes(t);
      if (n == 1) return fl(v.f[0]);
      std::string s = t->k == K::Color ? "rgb(" : "vec" + std::to_string(n) + "(";
      for (int i = 0; i < n; ++i) s += (i ? ", " : "") + fl(v.f[i]);
      return s + ")";
    }
  }
}

}  // namespace texdiff
