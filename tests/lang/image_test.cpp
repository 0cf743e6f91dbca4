// Image textures in lang/: decoding, the mip pyramid, lookups (filtered lookups tend to the
// mean), the image table's identity and thread safety, and the front end's image() builtin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <thread>
#include <vector>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>

#include "lang/image_table.h"
#include "lang/interpreter.h"
#include "lang/session.h"

using namespace tex::lang;
namespace fs = std::filesystem;

namespace {

const std::string kImages = std::string(TEX_SOURCE_DIR) + "/tests/conformance/images/";

const LoadedImage& loadFixture(const std::string& name, bool data = false) {
  ImageLoadResult r = ImageTable::global().load(kImages + name, data);
  EXPECT_GE(r.handle, 0) << r.message;
  return *ImageTable::global().get(r.handle);
}

// A fresh directory per test for files the test writes.
fs::path scratchDir(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("tex_image_test_" + std::to_string(::getpid()) + "_" + name);
  fs::create_directories(dir);
  return dir;
}

ImageLevel checkerLevel(int size, int cell) {
  ImageLevel l;
  l.width = l.height = size;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      float v = ((x / cell) + (y / cell)) % 2 == 0 ? 1.0f : 0.0f;
      l.rgba.insert(l.rgba.end(), {v, v, v, 1.0f});
    }
  return l;
}

}  // namespace

TEST(ImageDecode, PngRgbaFixtureDecodesToLinear) {
  const LoadedImage& quad = loadFixture("quad.png");
  ASSERT_EQ(quad.levels[0].width, 2);
  ASSERT_EQ(quad.levels[0].height, 2);
  const std::vector<float> want = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 51.0f * (1.0f / 255.0f)};
  EXPECT_EQ(quad.levels[0].decoded(), want);
}

TEST(ImageDecode, SrgbDecodeOnlyForColourImages) {
  const LoadedImage& colour = loadFixture("ramp.png", false);
  const LoadedImage& data = loadFixture("ramp.png", true);
  EXPECT_NE(&colour, &data);  // two table entries: two decodings of one file
  EXPECT_FLOAT_EQ(data.levels[0].decoded()[4], 64.0f / 255.0f);
  EXPECT_NEAR(colour.levels[0].decoded()[4], 0.0512694584, 1e-6);
  EXPECT_NEAR(colour.levels[0].decoded()[8], std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4), 1e-6);
  EXPECT_EQ(colour.levels[0].decoded()[12], 1.0f);  // 255 is 1 in both encodings
  EXPECT_EQ(colour.levels[0].decoded()[7], 1.0f);   // alpha of an opaque grey PNG
}

TEST(ImageDecode, SrgbToLinearIsContinuousAtTheKnee) {
  EXPECT_NEAR(srgbToLinear(0.04045f), srgbToLinear(0.040451f), 1e-6);
  EXPECT_EQ(srgbToLinear(0.0f), 0.0f);
  EXPECT_NEAR(srgbToLinear(1.0f), 1.0f, 1e-6);
}

TEST(ImageDecode, ExrRgbAndLuminance) {
  const LoadedImage& hdr = loadFixture("hdr.exr");
  EXPECT_EQ(hdr.levels[0].rgba, (std::vector<float>{0.5f, 2, 4, 1, 0.25f, 0.125f, 8, 1, 1.5f, 3, 0.75f, 1, 16, 0, 1, 1}));
  const LoadedImage& lum = loadFixture("lum.exr");
  EXPECT_EQ(lum.levels[0].rgba, (std::vector<float>{0.25f, 0.25f, 0.25f, 1, 6, 6, 6, 1}));
}

// A 32-bit float OpenEXR keeps its values: no rounding to half precision (1.66134727 became
// 1.66113281) and no overflow past half's 65504 (1e5 became inf), nor underflow of 3e-8.
TEST(ImageDecode, FloatExrKeepsFullPrecisionAndRange) {
  const fs::path file = scratchDir("float_exr") / "float.exr";
  const std::vector<float> r = {1.66134727f, 1e5f}, g = {3e-8f, -2.5f}, b = {0.1f, 70000.0f};
  Imf::Header header(2, 1);
  for (const char* name : {"R", "G", "B"}) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  {
    Imf::OutputFile out(file.c_str(), header);
    Imf::FrameBuffer fb;
    fb.insert("R", Imf::Slice(Imf::FLOAT, (char*)r.data(), sizeof(float), 2 * sizeof(float)));
    fb.insert("G", Imf::Slice(Imf::FLOAT, (char*)g.data(), sizeof(float), 2 * sizeof(float)));
    fb.insert("B", Imf::Slice(Imf::FLOAT, (char*)b.data(), sizeof(float), 2 * sizeof(float)));
    out.setFrameBuffer(fb);
    out.writePixels(1);
  }
  ImageLevel level;
  std::string code, message;
  ASSERT_TRUE(decodeImageFile(file.string(), false, level, code, message)) << message;
  EXPECT_EQ(level.width, 2);
  EXPECT_EQ(level.height, 1);
  EXPECT_EQ(level.rgba, (std::vector<float>{r[0], g[0], b[0], 1.0f, r[1], g[1], b[1], 1.0f}));
}

// A float luminance-only EXR (Y, with or without A) keeps its precision too (it went through
// RgbaInputFile's half: 1e6 became inf, 1e-9 became 0), and an EXR with no R, G, B or Y channel
// (only Z; or layered names) is an error instead of a black image.
TEST(ImageDecode, FloatLuminanceExrKeepsItsValuesAndChannellessExrIsAnError) {
  const fs::path dir = scratchDir("luminance_exr");
  const std::vector<float> y = {1e6f, 1e-9f}, a = {0.5f, 1.0f};
  auto write = [&](const fs::path& file, std::vector<const char*> names) {
    Imf::Header header(2, 1);
    for (const char* name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile out(file.c_str(), header);
    Imf::FrameBuffer fb;
    for (const char* name : names)
      fb.insert(name, Imf::Slice(Imf::FLOAT, (char*)(std::string(name) == "A" ? a.data() : y.data()), sizeof(float),
                                 2 * sizeof(float)));
    out.setFrameBuffer(fb);
    out.writePixels(1);
  };
  write(dir / "y.exr", {"Y", "A"});
  ImageLevel level;
  std::string code, message;
  ASSERT_TRUE(decodeImageFile((dir / "y.exr").string(), false, level, code, message)) << message;
  EXPECT_EQ(level.rgba, (std::vector<float>{y[0], y[0], y[0], a[0], y[1], y[1], y[1], a[1]}));
  write(dir / "z.exr", {"Z"});
  EXPECT_FALSE(decodeImageFile((dir / "z.exr").string(), false, level, code, message));
  EXPECT_NE(message.find("no R, G, B or Y channel (it has: Z)"), std::string::npos) << message;
}

TEST(ImageDecode, ErrorsHaveCodes) {
  ImageLoadResult missing = ImageTable::global().load(kImages + "does_not_exist.png", false);
  EXPECT_EQ(missing.handle, -1);
  EXPECT_EQ(missing.code, "E0420");
  ImageLoadResult directory = ImageTable::global().load(kImages, false);
  EXPECT_EQ(directory.code, "E0420");
  ImageLoadResult text = ImageTable::global().load(kImages + "not_an_image.png", false);
  EXPECT_EQ(text.code, "E0421");
  ImageLoadResult truncated = ImageTable::global().load(kImages + "truncated.png", false);
  EXPECT_EQ(truncated.code, "E0421");
}

TEST(MipPyramid, LevelSizesHalveDownToOneTexel) {
  std::vector<ImageLevel> levels = buildMipPyramid(checkerLevel(64, 8));
  ASSERT_EQ(levels.size(), 7u);
  for (size_t i = 0; i < levels.size(); ++i) {
    EXPECT_EQ(levels[i].width, 64 >> i);
    EXPECT_EQ(levels[i].height, 64 >> i);
    EXPECT_EQ(levels[i].rgba.size(), size_t(levels[i].width * levels[i].height * 4));
  }
  // Levels 1-3 still resolve the 8-texel cells exactly; level 4 averages whole cell pairs.
  EXPECT_EQ(levels[3].rgba[0], 1.0f);
  EXPECT_EQ(levels[3].rgba[4], 0.0f);
  for (float v : levels[4].rgba) EXPECT_TRUE(v == 0.5f || v == 1.0f);
  EXPECT_EQ(levels[6].rgba, (std::vector<float>{0.5f, 0.5f, 0.5f, 1.0f}));
}

TEST(MipPyramid, NonPowerOfTwoSizesKeepTheMean) {
  ImageLevel base;
  base.width = 5;
  base.height = 3;
  double sum = 0;
  for (int i = 0; i < 15; ++i) {
    float v = float(i * i % 7);
    sum += v;
    base.rgba.insert(base.rgba.end(), {v, 2 * v, 0, 1});
  }
  std::vector<ImageLevel> levels = buildMipPyramid(base);
  ASSERT_EQ(levels.size(), 3u);  // 5x3, 2x1, 1x1
  EXPECT_EQ(levels[1].width, 2);
  EXPECT_EQ(levels[1].height, 1);
  // Each texel averages the block it covers; the 1x1 level averages the two blocks of 2 and 3 columns.
  double left = 0, right = 0;
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) (x < 2 ? left : right) += base.rgba[size_t(y * 5 + x) * 4];
  EXPECT_FLOAT_EQ(levels[1].rgba[0], float(left / 6));
  EXPECT_FLOAT_EQ(levels[1].rgba[4], float(right / 9));
  EXPECT_FLOAT_EQ(levels[2].rgba[1], 2 * (float(left / 6) + float(right / 9)) / 2);
  EXPECT_GT(std::abs(levels[2].rgba[0] - float(sum / 15)), 0.0f);  // block means, not the exact mean (documented)
}

TEST(ImageLookup, FilteredCheckerTendsToTheMeanAsTheFootprintGrows) {
  LoadedImage image;
  image.levels = buildMipPyramid(checkerLevel(64, 2));
  // Mean distance from the mean over many points, for footprints of 1/8 texel to the whole image.
  double previous = 1e9;
  for (int step = 0; step <= 9; ++step) {
    float footprint = std::ldexp(1.0f, step - 3) / 64.0f;  // in uv
    double deviation = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      float u = float((i * 0.61803398875) - std::floor(i * 0.61803398875));
      float v = float((i * 0.75487766625) - std::floor(i * 0.75487766625));
      float out[4];
      lookupImage(image, ImageFilter::Trilinear, int32_t(ImageWrap::Repeat), u, v, footprint, 0, 0, footprint, out);
      ASSERT_GE(out[0], 0.0f);
      ASSERT_LE(out[0], 1.0f);
      deviation += std::abs(out[0] - 0.5);
    }
    deviation /= n;
    EXPECT_LE(deviation, previous + 1e-9) << "footprint " << footprint;
    previous = deviation;
    if (step <= 3) {
      EXPECT_GT(deviation, 0.1) << "a footprint up to a texel keeps the pattern";
    }
    if (step >= 2 + 1 + 3) {
      EXPECT_EQ(deviation, 0.0) << "footprints past the cell pair see the mean only";
    }
  }
}

TEST(ImageLookup, TrilinearBlendsAdjacentLevels) {
  LoadedImage image;
  image.levels = buildMipPyramid(checkerLevel(16, 1));  // level 1 is 0.5 everywhere
  float u = 0.5f / 16, v = 0.5f / 16;  // a white texel centre
  float atLevel0[4], halfway[4], atLevel1[4];
  lookupImage(image, ImageFilter::Trilinear, 0, u, v, 1.0f / 16, 0, 0, 1.0f / 16, atLevel0);
  lookupImage(image, ImageFilter::Trilinear, 0, u, v, std::sqrt(2.0f) / 16, 0, 0, 0, halfway);
  lookupImage(image, ImageFilter::Trilinear, 0, u, v, 2.0f / 16, 0, 0, 0, atLevel1);
  EXPECT_EQ(atLevel0[0], 1.0f);
  EXPECT_NEAR(halfway[0], 0.75f, 1e-5);
  EXPECT_EQ(atLevel1[0], 0.5f);
  // The longer footprint axis decides (isotropic filtering), whichever derivative it is.
  float swapped[4];
  lookupImage(image, ImageFilter::Trilinear, 0, u, v, 0, 0, 0, 2.0f / 16, swapped);
  EXPECT_EQ(swapped[0], 0.5f);
}

TEST(ImageLookup, NonFiniteInputsAndBadHandlesGiveZeros) {
  const LoadedImage& quad = loadFixture("quad.png");
  float out[4] = {9, 9, 9, 9};
  lookupImage(quad, ImageFilter::Bilinear, 0, std::nanf(""), 0.5f, 0, 0, 0, 0, out);
  EXPECT_EQ(std::vector<float>(out, out + 4), std::vector<float>(4, 0.0f));
  lookupImage(quad, ImageFilter::Nearest, 0, 0.5f, INFINITY, 0, 0, 0, 0, out);
  EXPECT_EQ(std::vector<float>(out, out + 4), std::vector<float>(4, 0.0f));
  // NaN derivatives fall back to the full-size level, infinite ones to the 1x1 level.
  lookupImage(quad, ImageFilter::Trilinear, 0, 0.25f, 0.25f, std::nanf(""), 0, 0, 0, out);
  EXPECT_EQ(out[0], 1.0f);
  lookupImage(quad, ImageFilter::Trilinear, 0, 0.25f, 0.25f, INFINITY, 0, 0, 0, out);
  EXPECT_EQ(out[0], quad.levels.back().rgba[0]);
  // A NaN on one axis is zero there: the other axis's footprint still picks the level, in
  // either order (a NaN duvdx had thrown away duvdy's).
  float nanFirst[4], nanSecond[4];
  lookupImage(quad, ImageFilter::Trilinear, 0, 0.25f, 0.25f, std::nanf(""), 0, 0, 100.0f, nanFirst);
  lookupImage(quad, ImageFilter::Trilinear, 0, 0.25f, 0.25f, 0, 100.0f, std::nanf(""), 0, nanSecond);
  EXPECT_EQ(nanFirst[0], quad.levels.back().rgba[0]);
  EXPECT_EQ(nanSecond[0], quad.levels.back().rgba[0]);
  imageLookup(-1, ImageFilter::Bilinear, 0, 0.5f, 0.5f, 0, 0, 0, 0, out);
  EXPECT_EQ(std::vector<float>(out, out + 4), std::vector<float>(4, 0.0f));
  imageLookup(1 << 30, ImageFilter::Bilinear, 0, 0.5f, 0.5f, 0, 0, 0, 0, out);
  EXPECT_EQ(out[3], 0.0f);
  float size[2] = {7, 7};
  imageSize(-5, size);
  EXPECT_EQ(size[0], 0.0f);
  // Huge coordinates stay in range (no overflow in the texel index).
  lookupImage(quad, ImageFilter::Bilinear, int32_t(ImageWrap::Mirror), 3e30f, -3e30f, 0, 0, 0, 0, out);
  EXPECT_TRUE(std::isfinite(out[0]));
}

TEST(ImageTableTest, SameFileLoadsOnceAndAChangedFileGetsANewHandle) {
  fs::path dir = scratchDir("reload");
  fs::copy_file(kImages + "quad.png", dir / "t.png", fs::copy_options::overwrite_existing);
  ImageLoadResult first = ImageTable::global().load((dir / "t.png").string(), false);
  ASSERT_GE(first.handle, 0);
  // Another spelling of the same path finds the same entry.
  ImageLoadResult again = ImageTable::global().load((dir / "." / "t.png").string(), false);
  EXPECT_EQ(again.handle, first.handle);
  const LoadedImage* firstImage = ImageTable::global().get(first.handle);
  EXPECT_EQ(ImageTable::global().resolve(firstImage->path, false, firstImage->fileBytes, firstImage->mtimeNs), first.handle);
  // Replace the file with a different image: a new handle; the old one still reads the old data.
  fs::copy_file(kImages + "odd.png", dir / "t.png", fs::copy_options::overwrite_existing);
  ImageLoadResult changed = ImageTable::global().load((dir / "t.png").string(), false);
  ASSERT_GE(changed.handle, 0);
  EXPECT_NE(changed.handle, first.handle);
  EXPECT_EQ(ImageTable::global().get(first.handle)->levels[0].width, 2);
  EXPECT_EQ(ImageTable::global().get(changed.handle)->levels[0].width, 3);
  // Compiled code resolves by the file's identity when it was checked: the old version keeps
  // its handle (a REPL value made before the change had followed the new file under the JIT),
  // and an identity this process never loaded gives the latest.
  const LoadedImage* changedImage = ImageTable::global().get(changed.handle);
  EXPECT_EQ(ImageTable::global().resolve(firstImage->path, false, firstImage->fileBytes, firstImage->mtimeNs), first.handle);
  EXPECT_EQ(ImageTable::global().resolve(changedImage->path, false, changedImage->fileBytes, changedImage->mtimeNs),
            changed.handle);
  EXPECT_EQ(ImageTable::global().resolve(firstImage->path, false, 1, 2), changed.handle);
  fs::remove_all(dir);
}

TEST(ImageTableTest, ParallelLoadsAreSafeAndDeduplicated) {
  fs::path dir = scratchDir("parallel");
  const int files = 12, threads = 8;
  for (int i = 0; i < files; ++i)
    fs::copy_file(kImages + (i % 2 ? "quad.png" : "checker.png"), dir / ("f" + std::to_string(i) + ".png"),
                  fs::copy_options::overwrite_existing);
  std::vector<std::vector<int32_t>> handles(threads, std::vector<int32_t>(files, -1));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int k = 0; k < files; ++k) {
        int i = (k + t) % files;  // each thread in another order
        ImageLoadResult r = ImageTable::global().load((dir / ("f" + std::to_string(i) + ".png")).string(), false);
        handles[size_t(t)][size_t(i)] = r.handle;
        // Lookups of images other threads are loading meanwhile.
        for (int j = 0; j < files; ++j) {
          int32_t h = handles[size_t(t)][size_t(j)];
          if (h < 0) continue;
          float out[4];
          imageLookup(h, ImageFilter::Trilinear, 0, 0.3f, 0.6f, 0.01f, 0, 0, 0.01f, out);
          ASSERT_TRUE(std::isfinite(out[0]));
        }
      }
    });
  for (auto& th : pool) th.join();
  std::set<int32_t> distinct;
  for (int i = 0; i < files; ++i) {
    ASSERT_GE(handles[0][size_t(i)], 0);
    for (int t = 1; t < threads; ++t) EXPECT_EQ(handles[size_t(t)][size_t(i)], handles[0][size_t(i)]) << "file " << i;
    distinct.insert(handles[0][size_t(i)]);
    EXPECT_EQ(ImageTable::global().get(handles[0][size_t(i)])->levels[0].width, i % 2 ? 2 : 64);
  }
  EXPECT_EQ(distinct.size(), size_t(files));
  fs::remove_all(dir);
}

TEST(ImageBuiltin, PathsResolveAgainstTheModulesDirectory) {
  Session session;
  ModuleInfo* m = session.loadSource(kImages + "inline.tex", "export fn f() -> Vec2 = image_size(image(\"odd.png\"))\n");
  ASSERT_NE(m, nullptr);
  int fn = session.instantiate(m, "f", {}, Span{});
  for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(fn, 0);
  Value v = evaluate(session.program(), fn, {}, WavelengthGroup{});
  EXPECT_EQ(v.f[0], 3.0f);
  EXPECT_EQ(v.f[1], 1.0f);
  EXPECT_EQ(formatValue(evaluate(session.program(), session.instantiate(m, "f", {}, Span{}), {}, WavelengthGroup{}),
                        TypeTable::global().vec(2), WavelengthGroup{}),
            "vec2(3.0, 1.0)");
}

// A module reached through a symlink finds its images where it finds its imports: beside the
// file the link points to (images had come from the link's directory, imports from the
// target's, so one file read two different neighbourhoods).
TEST(ImageBuiltin, ImagesAndImportsOfASymlinkedModuleResolveFromOneDirectory) {
  fs::path dir = scratchDir("symlinked");
  fs::create_directories(dir / "X");
  fs::create_directories(dir / "Y");
  fs::copy_file(kImages + "quad.png", dir / "X" / "i.png", fs::copy_options::overwrite_existing);  // 2x2
  fs::copy_file(kImages + "odd.png", dir / "Y" / "i.png", fs::copy_options::overwrite_existing);   // 3x1
  std::ofstream(dir / "X" / "lib.tex") << "export fn v() -> Float = 1.0\n";
  std::ofstream(dir / "Y" / "lib.tex") << "export fn v() -> Float = 0.0\n";
  std::ofstream(dir / "Y" / "main.tex") << "import lib\nexport fn f() -> Vec2 = image_size(image(\"i.png\")) + vec2(lib.v(), 0.0)\n";
  fs::create_symlink(fs::path("..") / "Y" / "main.tex", dir / "X" / "main.tex");
  Session session;
  ModuleInfo* m = session.loadFile((dir / "X" / "main.tex").string());
  ASSERT_NE(m, nullptr);
  const int fn = session.instantiate(m, "f", {}, Span{});
  for (auto& d : session.diags().items()) ADD_FAILURE() << renderDiagnostic(d);
  ASSERT_GE(fn, 0);
  const Value v = evaluate(session.program(), fn, {}, WavelengthGroup{});
  EXPECT_EQ(v.f[0], 3.0f);  // Y's image and Y's lib (v = 0)
  EXPECT_EQ(v.f[1], 1.0f);
  fs::remove_all(dir);
}

TEST(ImageBuiltin, ImageValuesPrintTheirFileAndSize) {
  Session session;
  ModuleInfo* m = session.loadSource(kImages + "inline.tex", "export fn f() -> Image = image(\"quad.png\")\n");
  ASSERT_NE(m, nullptr);
  int fn = session.instantiate(m, "f", {}, Span{});
  ASSERT_GE(fn, 0);
  Value v = evaluate(session.program(), fn, {}, WavelengthGroup{});
  EXPECT_EQ(formatValue(v, TypeTable::global().image(), WavelengthGroup{}), "<image quad.png 2x2>");
  EXPECT_EQ(typeName(TypeTable::global().image()), "Image");
}

// PNG texels stay as their 8- or 16-bit codes (a quarter or half of float RGBA), decoded per
// lookup through tables: every lookup (each filter and wrap mode, footprints from magnified to
// beyond the last level) gives the same bits as an image held as decoded floats.
TEST(ImageLookup, StoredCodesLookUpAsTheDecodedFloats) {
  for (const char* name : {"noise.png", "deep.png"})
    for (const bool data : {false, true}) {
      const LoadedImage& stored = loadFixture(name, data);
      const ImageLevel& base = stored.levels[0];
      const size_t texels = size_t(base.width) * size_t(base.height);
      EXPECT_EQ(base.texelBytes(), texels * 4 * (std::string(name) == "deep.png" ? 2 : 1)) << name;
      ImageLevel floats;
      floats.width = base.width;
      floats.height = base.height;
      floats.rgba = base.decoded();
      LoadedImage reference;
      reference.levels = buildMipPyramid(floats);
      ASSERT_EQ(reference.levels.size(), stored.levels.size());
      for (size_t l = 1; l < stored.levels.size(); ++l) EXPECT_EQ(stored.levels[l].rgba, reference.levels[l].rgba) << name << " level " << l;
      uint32_t state = 7;
      const auto uniform = [&state](float lo, float hi) {
        state = state * 1664525u + 1013904223u;
        return lo + (hi - lo) * float(state >> 8) * 0x1p-24f;
      };
      for (int i = 0; i < 4000; ++i) {
        const float u = uniform(-1.5f, 2.5f), v = uniform(-1.5f, 2.5f), d = std::exp2(uniform(-8.0f, 2.0f));
        const ImageFilter filter = ImageFilter(i % 3);
        const int32_t wrap = i / 3 % 3;
        float got[4], want[4];
        lookupImage(stored, filter, wrap, u, v, d, 0.3f * d, -0.2f * d, d, got);
        lookupImage(reference, filter, wrap, u, v, d, 0.3f * d, -0.2f * d, d, want);
        for (int c = 0; c < 4; ++c) ASSERT_EQ(got[c], want[c]) << name << (data ? " data" : " colour") << " lookup " << i;
      }
    }
}
