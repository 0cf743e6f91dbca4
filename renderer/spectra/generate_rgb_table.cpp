// Fits the RGB-to-spectrum coefficient table of Jakob & Hanika 2019, "A Low-Dimensional
// Function Space for Efficient Spectral Upsampling" (Computer Graphics Forum 38(2)), for linear
// sRGB reflectances under D65 with the CIE 1931 2-degree observer.
//
// Run by the build (renderer/CMakeLists.txt): generate_rgb_table <output.bin> [resolution]
// Output (native little-endian, layout in rgb_table_format.h): header, z nodes, x/y nodes, then
// coefficients [3][res z][res y][res x][3] in nm units (s(lambda) = sigmoid(c0 l^2 + c1 l + c2)).
//
// Method: as the paper, the cube is split into 3 regions by its largest component l; inside one,
// a colour is (z, x z, y z) up to a rotation of the channels. The paper warps z by
// smoothstep(smoothstep(k / (res - 1))) so that slices crowd near black and white; we warp x
// and y the same way (the paper's are uniform): near white and near the cube's edges the
// coefficients grow fast and trilinear interpolation between uniform nodes misses the colour
// by up to 1.4e-2 at resolution 64, the warped nodes by 1.2e-3 (linear sRGB, 20k random colours).
// Each cell's 3 coefficients solve 3 equations: the CIELAB colour of the spectrum under D65
// equals the target's. We solve them with damped Gauss-Newton (Levenberg-Marquardt) and an
// analytic Jacobian, by continuation: starting at (z = zNodes[res/5], x = y ~ 1/2) from the
// zero polynomial (a flat 1/2 spectrum), every cell starts from the solution of an already
// solved neighbour nearer that centre. The quadrature is the one color::reflectanceSpectrumToXyz
// uses (1 nm steps over 360..830 nm), so the table's fit is exact for that integral.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "renderer/color/cie_tables.h"
#include "renderer/color/color.h"
#include "renderer/spectra/rgb_table_format.h"

namespace {

using tex::render::RgbTableHeader;

constexpr double kLambdaMinNm = 360.0, kLambdaMaxNm = 830.0;

// Quadrature nodes with nonzero weight: t = normalised wavelength in [0,1] and the weights
// that turn reflectance samples into XYZ (normalised so that R = 1 has Y = 1).
struct Quadrature {
  std::vector<double> t, wx, wy, wz;
  double whiteX = 0, whiteY = 0, whiteZ = 0;  // Lab reference white: linear sRGB (1,1,1)
};

Quadrature makeQuadrature() {
  Quadrature q;
  double ySum = 0;
  for (int i = 0; i < tex::color::kCieSampleCount; ++i) {
    const float lambda = float(tex::color::kCieLambdaMinNm + i);
    ySum += double(tex::color::kCie1931Y[i]) * tex::color::d65RelativePower(lambda);
  }
  for (int i = 0; i < tex::color::kCieSampleCount; ++i) {
    const float lambda = float(tex::color::kCieLambdaMinNm + i);
    const double d65 = tex::color::d65RelativePower(lambda);
    if (d65 == 0.0) continue;
    q.t.push_back((lambda - kLambdaMinNm) / (kLambdaMaxNm - kLambdaMinNm));
    q.wx.push_back(tex::color::kCie1931X[i] * d65 / ySum);
    q.wy.push_back(tex::color::kCie1931Y[i] * d65 / ySum);
    q.wz.push_back(tex::color::kCie1931Z[i] * d65 / ySum);
  }
  const tex::color::Xyz white = tex::color::linearSrgbToXyz({1.0f, 1.0f, 1.0f});
  q.whiteX = white.x, q.whiteY = white.y, q.whiteZ = white.z;
  return q;
}

// CIELAB's f and its derivative (CIE 15:2004).
constexpr double kLabDelta = 6.0 / 29.0;
double labF(double v) {
  return v > kLabDelta * kLabDelta * kLabDelta ? std::cbrt(v) : v / (3 * kLabDelta * kLabDelta) + 4.0 / 29.0;
}
double labFPrime(double v) {
  if (v > kLabDelta * kLabDelta * kLabDelta) {
    const double c = std::cbrt(v);
    return 1.0 / (3.0 * c * c);
  }
  return 1.0 / (3 * kLabDelta * kLabDelta);
}

void xyzToLab(const Quadrature& q, const double xyz[3], double lab[3], double dLabDXyz[3][3]) {
  const double fx = labF(xyz[0] / q.whiteX), fy = labF(xyz[1] / q.whiteY), fz = labF(xyz[2] / q.whiteZ);
  lab[0] = 116 * fy - 16;
  lab[1] = 500 * (fx - fy);
  lab[2] = 200 * (fy - fz);
  if (!dLabDXyz) return;
  const double dx = labFPrime(xyz[0] / q.whiteX) / q.whiteX;
  const double dy = labFPrime(xyz[1] / q.whiteY) / q.whiteY;
  const double dz = labFPrime(xyz[2] / q.whiteZ) / q.whiteZ;
  dLabDXyz[0][0] = 0, dLabDXyz[0][1] = 116 * dy, dLabDXyz[0][2] = 0;
  dLabDXyz[1][0] = 500 * dx, dLabDXyz[1][1] = -500 * dy, dLabDXyz[1][2] = 0;
  dLabDXyz[2][0] = 0, dLabDXyz[2][1] = 200 * dy, dLabDXyz[2][2] = -200 * dz;
}

// Residual r = Lab(spectrum(c)) - target and its Jacobian dr/dc, c in normalised-t units.
void residual(const Quadrature& q, const double c[3], const double targetLab[3], double r[3],
              double jac[3][3]) {
  double xyz[3] = {0, 0, 0};
  double dXyz[3][3] = {};  // dXyz[channel][coefficient]
  const size_t n = q.t.size();
  for (size_t i = 0; i < n; ++i) {
    const double t = q.t[i];
    const double x = (c[0] * t + c[1]) * t + c[2];
    const double inv = 1.0 / std::sqrt(1.0 + x * x);
    const double s = 0.5 + 0.5 * x * inv;
    const double ds = 0.5 * inv * inv * inv;  // d sigmoid / dx
    const double basis[3] = {t * t, t, 1.0};
    const double w[3] = {q.wx[i], q.wy[i], q.wz[i]};
    for (int ch = 0; ch < 3; ++ch) {
      xyz[ch] += w[ch] * s;
      for (int k = 0; k < 3; ++k) dXyz[ch][k] += w[ch] * ds * basis[k];
    }
  }
  double lab[3], dLab[3][3];
  xyzToLab(q, xyz, lab, dLab);
  for (int i = 0; i < 3; ++i) {
    r[i] = lab[i] - targetLab[i];
    for (int k = 0; k < 3; ++k) {
      jac[i][k] = dLab[i][0] * dXyz[0][k] + dLab[i][1] * dXyz[1][k] + dLab[i][2] * dXyz[2][k];
    }
  }
}

bool solve3(double a[3][3], double b[3], double x[3]) {
  // Gaussian elimination with partial pivoting.
  int perm[3] = {0, 1, 2};
  for (int col = 0; col < 3; ++col) {
    int pivot = col;
    for (int row = col + 1; row < 3; ++row)
      if (std::abs(a[perm[row]][col]) > std::abs(a[perm[pivot]][col])) pivot = row;
    std::swap(perm[col], perm[pivot]);
    const double d = a[perm[col]][col];
    if (std::abs(d) < 1e-300) return false;
    for (int row = col + 1; row < 3; ++row) {
      const double f = a[perm[row]][col] / d;
      for (int k = col; k < 3; ++k) a[perm[row]][k] -= f * a[perm[col]][k];
      b[perm[row]] -= f * b[perm[col]];
    }
  }
  for (int col = 2; col >= 0; --col) {
    double s = b[perm[col]];
    for (int k = col + 1; k < 3; ++k) s -= a[perm[col]][k] * x[k];
    x[col] = s / a[perm[col]][col];
  }
  return true;
}

double norm2(const double r[3]) { return r[0] * r[0] + r[1] * r[1] + r[2] * r[2]; }

// Levenberg-Marquardt on the 3x3 system; returns the final Lab residual norm.
double fit(const Quadrature& q, const double rgb[3], double c[3]) {
  const tex::color::Xyz target = tex::color::linearSrgbToXyz({float(rgb[0]), float(rgb[1]), float(rgb[2])});
  const double targetXyz[3] = {target.x, target.y, target.z};
  double targetLab[3];
  xyzToLab(q, targetXyz, targetLab, nullptr);

  double r[3], jac[3][3];
  residual(q, c, targetLab, r, jac);
  double cost = norm2(r);
  double mu = 1e-8;
  for (int iter = 0; iter < 60 && cost > 1e-14; ++iter) {
    bool accepted = false;
    while (!accepted && mu < 1e12) {
      // (J^T J + mu diag(J^T J)) delta = -J^T r
      double a[3][3], b[3], delta[3];
      for (int i = 0; i < 3; ++i) {
        b[i] = 0;
        for (int k = 0; k < 3; ++k) {
          a[i][k] = 0;
          for (int m = 0; m < 3; ++m) a[i][k] += jac[m][i] * jac[m][k];
        }
        for (int m = 0; m < 3; ++m) b[i] -= jac[m][i] * r[m];
      }
      for (int i = 0; i < 3; ++i) a[i][i] *= 1.0 + mu;
      if (!solve3(a, b, delta)) {
        mu *= 10;
        continue;
      }
      const double trial[3] = {c[0] + delta[0], c[1] + delta[1], c[2] + delta[2]};
      double rTrial[3], jacTrial[3][3];
      residual(q, trial, targetLab, rTrial, jacTrial);
      const double costTrial = norm2(rTrial);
      if (costTrial < cost) {
        for (int i = 0; i < 3; ++i) {
          c[i] = trial[i], r[i] = rTrial[i];
          for (int k = 0; k < 3; ++k) jac[i][k] = jacTrial[i][k];
        }
        cost = costTrial;
        mu = std::max(mu * 0.1, 1e-12);
        accepted = true;
      } else {
        mu *= 10;
      }
    }
    if (!accepted) break;  // no descent left (e.g. white: only reached asymptotically)
  }
  return std::sqrt(cost);
}

struct Table {
  int res = 0;
  std::vector<float> zNodes, xyNodes;
  std::vector<double> coeffs;  // [3][res][res][res][3], normalised-t units while fitting
  std::vector<double> labResidual;
  double& at(int l, int k, int j, int i, int c) {
    return coeffs[((((size_t(l) * res + k) * res + j) * res + i) * 3) + c];
  }
  double& residualAt(int l, int k, int j, int i) {
    return labResidual[((size_t(l) * res + k) * res + j) * res + i];
  }
};

double smoothstep(double x) { return x * x * (3.0 - 2.0 * x); }


// Solves cell (l, k, j, i) starting from the coefficients `init`.
void solveCell(const Quadrature& q, Table& table, int l, int k, int j, int i, const double init[3]) {
  const double z = table.zNodes[k];
  const double x = table.xyNodes[i], y = table.xyNodes[j];
  double rgb[3];
  rgb[l] = z;
  rgb[(l + 1) % 3] = x * z;
  rgb[(l + 2) % 3] = y * z;
  double c[3] = {init[0], init[1], init[2]};
  table.residualAt(l, k, j, i) = fit(q, rgb, c);
  for (int m = 0; m < 3; ++m) table.at(l, k, j, i, m) = c[m];
}

void copyCell(Table& table, int l, int k, int j, int i, double out[3]) {
  for (int m = 0; m < 3; ++m) out[m] = table.at(l, k, j, i, m);
}

// One z slice, marching outwards from the already solved centre cell (ci, ci).
void solveSlice(const Quadrature& q, Table& table, int l, int k) {
  const int res = table.res, centre = res / 2;
  double init[3];
  for (int dir : {+1, -1}) {  // the row j = centre
    for (int i = centre + dir; i >= 0 && i < res; i += dir) {
      copyCell(table, l, k, centre, i - dir, init);
      solveCell(q, table, l, k, centre, i, init);
    }
  }
  for (int i = 0; i < res; ++i) {  // every column, from its row-centre cell
    for (int dir : {+1, -1}) {
      for (int j = centre + dir; j >= 0 && j < res; j += dir) {
        copyCell(table, l, k, j - dir, i, init);
        solveCell(q, table, l, k, j, i, init);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: generate_rgb_table <output.bin> [resolution]\n");
    return 2;
  }
  const int res = argc > 2 ? std::atoi(argv[2]) : 64;
  if (res < 4 || res > 256) {
    std::fprintf(stderr, "generate_rgb_table: resolution must be in 4..256\n");
    return 2;
  }
  const Quadrature q = makeQuadrature();
  Table table;
  table.res = res;
  table.zNodes.resize(res);
  table.xyNodes.resize(res);
  for (int k = 0; k < res; ++k) {
    table.zNodes[k] = float(smoothstep(smoothstep(double(k) / (res - 1))));
    table.xyNodes[k] = table.zNodes[k];
  }
  table.coeffs.assign(size_t(3) * res * res * res * 3, 0.0);
  table.labResidual.assign(size_t(3) * res * res * res, 0.0);

  const int startK = res / 5, centre = res / 2;
  const int threadCount = int(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
  for (int l = 0; l < 3; ++l) {
    // The centre column (x = y = 1/2) from a flat 1/2 spectrum, outwards in z. Slice 0 is
    // black, which the sigmoid reaches only at infinity: it copies slice 1 (z ~ 2e-6 at res 64).
    const double zero[3] = {0, 0, 0};
    solveCell(q, table, l, startK, centre, centre, zero);
    double init[3];
    for (int k = startK + 1; k < res; ++k) {
      copyCell(table, l, k - 1, centre, centre, init);
      solveCell(q, table, l, k, centre, centre, init);
    }
    for (int k = startK - 1; k >= 1; --k) {
      copyCell(table, l, k + 1, centre, centre, init);
      solveCell(q, table, l, k, centre, centre, init);
    }
    std::atomic<int> nextK{1};
    std::vector<std::thread> workers;
    for (int w = 0; w < threadCount; ++w) {
      workers.emplace_back([&] {
        for (int k; (k = nextK.fetch_add(1)) < res;) solveSlice(q, table, l, k);
      });
    }
    for (std::thread& t : workers) t.join();
    for (int j = 0; j < res; ++j)
      for (int i = 0; i < res; ++i) {
        for (int m = 0; m < 3; ++m) table.at(l, 0, j, i, m) = table.at(l, 1, j, i, m);
        table.residualAt(l, 0, j, i) = 0;
      }
  }

  // Statistics: Lab residuals, excluding the white corner (reachable only asymptotically).
  double maxResidual = 0, sumResidual = 0;
  int bad = 0;
  for (int l = 0; l < 3; ++l)
    for (int k = 0; k < res; ++k)
      for (int j = 0; j < res; ++j)
        for (int i = 0; i < res; ++i) {
          if (k == res - 1 && j == res - 1 && i == res - 1) continue;
          const double r = table.residualAt(l, k, j, i);
          maxResidual = std::max(maxResidual, r);
          sumResidual += r;
          bad += r > 1e-3;
        }
  std::printf("generate_rgb_table: res %d, Lab residual max %.3g mean %.3g, %d cells above 1e-3\n", res,
              maxResidual, sumResidual / (3.0 * res * res * res), bad);

  // From normalised t = (lambda - 360) / 470 to lambda in nm.
  std::vector<float> out(table.coeffs.size());
  const double a = kLambdaMinNm, b = 1.0 / (kLambdaMaxNm - kLambdaMinNm);
  for (size_t cell = 0; cell < table.coeffs.size(); cell += 3) {
    const double c0 = table.coeffs[cell], c1 = table.coeffs[cell + 1], c2 = table.coeffs[cell + 2];
    out[cell + 0] = float(c0 * b * b);
    out[cell + 1] = float(c1 * b - 2.0 * c0 * a * b * b);
    out[cell + 2] = float(c2 - c1 * a * b + c0 * a * a * b * b);
  }

  FILE* file = std::fopen(argv[1], "wb");
  if (!file) {
    std::perror(argv[1]);
    return 1;
  }
  RgbTableHeader header;
  header.resolution = uint32_t(res);
  bool ok = std::fwrite(&header, sizeof header, 1, file) == 1;
  ok = ok && std::fwrite(table.zNodes.data(), sizeof(float), table.zNodes.size(), file) == table.zNodes.size();
  ok = ok && std::fwrite(table.xyNodes.data(), sizeof(float), table.xyNodes.size(), file) == table.xyNodes.size();
  ok = ok && std::fwrite(out.data(), sizeof(float), out.size(), file) == out.size();
  ok = (std::fclose(file) == 0) && ok;
  if (!ok) {
    std::fprintf(stderr, "generate_rgb_table: cannot write %s\n", argv[1]);
    std::remove(argv[1]);
    return 1;
  }
  return 0;
}
