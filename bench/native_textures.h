// Hand-written C++ equivalents of the textures in bench/textures.tex, the baseline for the JIT
// benchmark (bench/bench_jit.cpp). Each computes exactly the function its .tex twin computes
// (the same hashes, gradients and octave loops; float32 arithmetic in the same order; tex's
// NaN-aware min/max and saturating float-to-int), and is compiled with -O2 -march=native
// -ffp-contract=off (the language forbids FMA contraction), no fast-math.
#pragma once
#include "compiler/abi.h"

namespace tex::bench {

using compiler::HitAbi;

// Writes the texture's value at `h` to `out`: 1 float (Float), 3 (Color) or one per wavelength
// (Spectrum, at `lambda`; the non-spectral textures ignore it).
using NativeFn = void (*)(const HitAbi& h, const float* lambda, float* out);

struct NativeTexture {
  const char* name;   // the exported function in bench/textures.tex
  NativeFn fn;        // 4 wavelengths for spectra
  NativeFn fn1;       // spectra only: the same with 1 wavelength (else null)
  int outWords;       // with 4 wavelengths
  bool spectral;
};

// Every texture of bench/textures.tex, in file order; `count` receives the number.
const NativeTexture* nativeTextures(int& count);

void native_perlin_tex(const HitAbi& h, const float* lambda, float* out);
void native_fbm_tex(const HitAbi& h, const float* lambda, float* out);
void native_value_tex(const HitAbi& h, const float* lambda, float* out);
void native_worley_tex(const HitAbi& h, const float* lambda, float* out);
void native_marble(const HitAbi& h, const float* lambda, float* out);
void native_marble_classic(const HitAbi& h, const float* lambda, float* out);
void native_wood(const HitAbi& h, const float* lambda, float* out);
void native_bricks_tex(const HitAbi& h, const float* lambda, float* out);
void native_checker_tex(const HitAbi& h, const float* lambda, float* out);
void native_cells_tex(const HitAbi& h, const float* lambda, float* out);
void native_ior_cauchy(const HitAbi& h, const float* lambda, float* out);
void native_blackbody(const HitAbi& h, const float* lambda, float* out);
void native_thin_film(const HitAbi& h, const float* lambda, float* out);

}  // namespace tex::bench
