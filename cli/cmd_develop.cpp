// `tex develop`: sample files to an image at any resolution and filter.
#include <algorithm>
#include <chrono>
#include <new>
#include <optional>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "cli/command.h"
#include "cli/options.h"
#include "cli/option_values.h"
#include "renderer/film/film.h"
#include "renderer/io/sample_file.h"
#include "renderer/sampling/sampler.h"

namespace tex::cli {

namespace {

const char* kDevelopUsage =
    "usage: tex develop SAMPLES... -o OUT.exr|OUT.png [options]\n"
    "\n"
    "Develops sample files (written by --samples-out) into an image. The samples are a\n"
    "continuous image: any resolution and filter can be chosen. Several files (e.g. index\n"
    "ranges rendered by different processes or machines) are merged; the result is\n"
    "bit-identical to developing one file holding the same ranges. Files must come from the\n"
    "same render: scene, seed, sampler, wavelengths, integrator and image size.\n"
    "\n"
    "options:\n"
    "  -o, --output PATH       .exr (float RGB + metadata) or .png (8-bit sRGB)\n"
    "  --res WxH               resolution (default: the render's, as its sample file records it;\n"
    "                          512x512 for files that do not)\n"
    "  --filter NAME           box | tent | gaussian | mitchell (default box)\n"
    "  --estimator NAME        weighted (sum a c / sum a, default) | density (sum a c * W*H / N)\n"
    "  --half                  write half-float EXR channels\n"
    "  --no-variance           omit the variance.R/G/B channels (EXR)\n"
    "  --spectral-bins N       add N spectral channels over 360-830 nm (EXR, spectral files)\n"
    "  --thumbnail PATH        also write a relative-variance thumbnail (PNG or EXR)\n"
    "  -q, --quiet             no summary on stderr\n";

int usage(const std::string& message) {
  std::fprintf(stderr, "tex develop: error: %s\n%s", message.c_str(), kDevelopUsage);
  return 2;
}

std::string isoTimeNow() {
  const std::time_t now = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return buffer;
}

}  // namespace

int runDevelop(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kDevelopUsage, stdout);
    return 0;
  }
  std::vector<std::string> inputs;
  std::string output, thumbnail;
  FilmSettings settings;
  settings.width = settings.height = 0;  // 0: from the files, else 512x512
  bool resolutionGiven = false;
  FilmEstimator estimator = FilmEstimator::Weighted;
  bool half = false, variance = true, quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&](std::string& out) { return takeValue(args, i, out); };
    std::string v;
    if (a == "-o" || a == "--output") {
      if (!value(output)) return usage("-o needs a path");
    } else if (a == "--res") {
      if (!value(v) || !parseResolution(v, settings.width, settings.height)) return usage("--res needs WxH, e.g. 640x480");
      resolutionGiven = true;
    } else if (a == "--filter") {
      if (!value(v)) return usage("--filter needs a name");
      const auto kind = parseFilterKind(v);
      if (!kind) return usage("unknown filter '" + v + "' (box, tent, gaussian, mitchell)");
      settings.filter = *kind;
    } else if (a == "--estimator") {
      if (!value(v) || (v != "weighted" && v != "density")) return usage("--estimator needs weighted or density");
      estimator = v == "weighted" ? FilmEstimator::Weighted : FilmEstimator::Density;
    } else if (a == "--half") {
      half = true;
    } else if (a == "--no-variance") {
      variance = false;
    } else if (a == "--spectral-bins") {
      if (!value(v) || !parseIntInRange(v, settings.spectralBins, 0, 470)) return usage("--spectral-bins needs 0..470");
    } else if (a == "--thumbnail") {
      if (!value(thumbnail)) return usage("--thumbnail needs a path");
    } else if (a == "-q" || a == "--quiet") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option '" + a + "'");
    } else {
      inputs.push_back(a);
    }
  }
  if (inputs.empty()) return usage("no sample file given");
  if (output.empty()) return usage("no output given (-o OUT.exr)");
  const std::string extension = std::filesystem::path(output).extension().string();
  if (extension != ".exr" && extension != ".png") return usage("output must end in .exr or .png, got '" + output + "'");
  if (extension == ".png" && settings.spectralBins > 0) return usage("--spectral-bins needs an .exr output");
  if (const std::string problem = outputDirectoryProblem(output); !problem.empty()) {
    std::fprintf(stderr, "tex develop: error: %s\n", problem.c_str());
    return 1;
  }
  // Every output is checked before any work, and none may be another output or an input: a
  // thumbnail named like -o replaced the image, and -o named like an input overwrote it.
  if (!thumbnail.empty()) {
    const std::string thumbExtension = std::filesystem::path(thumbnail).extension().string();
    if (thumbExtension != ".exr" && thumbExtension != ".png")
      return usage("--thumbnail must end in .exr or .png, got '" + thumbnail + "'");
    if (const std::string problem = outputDirectoryProblem(thumbnail); !problem.empty()) {
      std::fprintf(stderr, "tex develop: error: %s\n", problem.c_str());
      return 1;
    }
  }
  {
    if (!thumbnail.empty() && samePath(thumbnail, output)) return usage("--thumbnail and -o name the same file");
    for (const std::string& input : inputs) {
      if (samePath(input, output)) return usage("-o names the input " + input + " (it would be overwritten)");
      if (!thumbnail.empty() && samePath(input, thumbnail)) return usage("--thumbnail names the input " + input);
    }
  }

  // Headers first: the files must describe the same render and disjoint index ranges.
  const auto start = std::chrono::steady_clock::now();
  std::vector<SampleFileInfo> infos(inputs.size());
  std::vector<runtime::IndexRange> allRanges;
  for (size_t k = 0; k < inputs.size(); ++k) {
    if (std::string e = readSampleFileInfo(inputs[k], infos[k]); !e.empty()) {
      std::fprintf(stderr, "tex develop: error: %s\n", e.c_str());
      return 1;
    }
    const SampleFileHeader& h = infos[k].header;
    const SampleFileHeader& first = infos[0].header;
    // Sampler, wavelength count and integrator too: renders that differ in them would merge
    // into an image whose metadata (copied from the first file) describes neither.
    std::string differs;
    if (h.sceneHash != first.sceneHash) differs = "scene hash";
    else if (h.seed != first.seed) differs = "seed";
    else if (h.valueKind != first.valueKind) differs = "value kind";
    else if (h.sampler != first.sampler) differs = "sampler";
    else if (h.wavelengthsPerRecord != first.wavelengthsPerRecord) differs = "wavelengths per path";
    else if (h.integrator != first.integrator) differs = "integrator";
    // Renders at other sizes map their sample indices to other pixels: their samples would
    // not fill the pixels as either render's do, and the default size would be the first's.
    else if (h.imageWidth != first.imageWidth || h.imageHeight != first.imageHeight) differs = "recorded image size";
    if (!differs.empty()) {
      std::fprintf(stderr, "tex develop: error: %s: not from the same render as %s (the %s differs)\n", inputs[k].c_str(),
                   inputs[0].c_str(), differs.c_str());
      return 1;
    }
    allRanges.insert(allRanges.end(), infos[k].ranges.begin(), infos[k].ranges.end());
  }
  if (runtime::rangesOverlap(allRanges)) {
    std::string names;
    for (const std::string& input : inputs) names += (names.empty() ? "" : ", ") + input;
    std::fprintf(stderr, "tex develop: error: %s: the sample files overlap in their index ranges (samples would count twice)\n",
                 names.c_str());
    return 1;
  }
  if (settings.width == 0) {
    // The render's own size: a non-square render developed at the old 512x512 default came out
    // stretched.
    const SampleFileHeader& h = infos[0].header;
    const bool recorded = h.imageWidth > 0 && h.imageHeight > 0 && h.imageWidth <= 65536 && h.imageHeight <= 65536;
    settings.width = recorded ? int(h.imageWidth) : 512;
    settings.height = recorded ? int(h.imageHeight) : 512;
  }
  settings.valueKind = infos[0].header.valueKind;
  if (settings.valueKind == ValueKind::Scalar && settings.spectralBins > 0) {
    if (!quiet)
      std::fprintf(stderr, "tex develop: warning: %s holds scalar values, not spectra: --spectral-bins is ignored\n",
                   inputs[0].c_str());
    settings.spectralBins = 0;
  }

  std::optional<FilmAccumulator> filmStorage;
  try {
    filmStorage.emplace(settings);
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "tex develop: error: a %dx%d film does not fit in memory (%s; give a smaller --res)\n",
                 settings.width, settings.height,
                 resolutionGiven ? "the --res given" : ("the size " + inputs[0] + " records").c_str());
    return 1;
  }
  FilmAccumulator& film = *filmStorage;
  uint64_t records = 0;
  for (size_t k = 0; k < inputs.size(); ++k) {
    SampleFileInfo info;
    const std::string e = readSampleFile(inputs[k], info, [&](runtime::IndexRange, std::span<const SampleRecord> chunk) {
      film.add(chunk.data(), chunk.size());
    });
    if (!e.empty()) {
      std::fprintf(stderr, "tex develop: error: %s\n", e.c_str());
      return 1;
    }
    if (!info.complete && !quiet) {
      std::fprintf(stderr, "tex develop: warning: %s has no footer (its writer stopped early); using its %llu whole chunks\n",
                   inputs[k].c_str(), (unsigned long long)info.chunks);
    }
    records += info.records;
  }
  const std::vector<runtime::IndexRange> ranges = runtime::mergeRanges(allRanges);
  const uint64_t samples = runtime::totalSize(ranges);
  const DevelopedImage image = film.develop(estimator, samples);
  if (image.unstablePixels > 0)
    std::fprintf(stderr, "tex develop: warning: in %llu pixels the filter's weights nearly cancel (too few samples per pixel for its negative lobes): their values are unreliable\n",
                 (unsigned long long)image.unstablePixels);
  // Developing finer than the samples (1 spp at 4x the resolution) leaves pixels without any
  // sample: black, which is no estimate of anything.
  uint64_t emptyPixels = 0;
  for (float w : image.weightSum) emptyPixels += !(w != 0.0f);
  if (!quiet && image.weightSum.size() > 0 && double(emptyPixels) > 0.01 * double(image.weightSum.size()))
    std::fprintf(stderr, "tex develop: warning: %llu of %zu pixels got no sample (the resolution is finer than the samples; a wider filter or a smaller --res fills them)\n",
                 (unsigned long long)emptyPixels, image.weightSum.size());
  if (image.saturatedPixels > 0)
    std::fprintf(stderr, "tex develop: warning: %llu pixels saturated the film (values beyond about 5e11 per pixel, summed over its samples): their values and variances are wrong\n",
                 (unsigned long long)image.saturatedPixels);

  const SampleFileHeader& h = infos[0].header;
  char hash[32];
  std::snprintf(hash, sizeof hash, "%016llx", (unsigned long long)h.sceneHash);
  const std::map<std::string, std::string> metadata = {
      {"tex.samples", std::to_string(samples)},
      {"tex.records", std::to_string(records)},
      {"tex.indexRanges", runtime::formatRanges(ranges)},
      {"tex.seed", std::to_string(h.seed)},
      {"tex.sceneHash", hash},
      {"tex.sampler", h.sampler <= 1 ? sampling::samplerName(sampling::SamplerKind(h.sampler)) : "unknown"},
      {"tex.integrator", h.integrator},
      {"tex.filter", filterName(settings.filter)},
      {"tex.estimator", estimator == FilmEstimator::Weighted ? "weighted" : "density"},
      {"tex.time", isoTimeNow()},
  };
  std::string error;
  const bool png = extension == ".png";
  if (png) {
    error = writeRgbImage(output, image.rgbImage());
  } else {
    const ExrImage exr = image.toExr(variance, settings.spectralBins > 0, metadata);
    if (half) {
      // Half floats end at 65504: larger values (bright pixels, and variances sooner) become
      // infinity, which tex compare then cannot test. Said, not silent.
      uint64_t overflowing = 0;
      for (const ExrChannel& c : exr.channels)
        for (float v : c.values) overflowing += std::isfinite(v) && std::fabs(v) > 65504.0f;
      if (overflowing > 0)
        std::fprintf(stderr, "tex develop: warning: %llu channel values exceed the half-float range (65504) and are written as infinity; drop --half to keep them\n",
                     (unsigned long long)overflowing);
    }
    error = writeExr(output, exr, half ? ExrPixelType::Half : ExrPixelType::Float);
  }
  if (!error.empty()) {
    std::fprintf(stderr, "tex develop: error: %s\n", error.c_str());
    return 1;
  }
  if (!thumbnail.empty()) {
    int tw = 0, th = 0;
    const std::vector<float> rel = image.relativeVarianceThumbnail(64, tw, th);
    RgbImage thumb{tw, th, std::vector<float>(size_t(tw) * th * 3)};
    for (size_t p = 0; p < rel.size(); ++p) {
      // Log scale: relative variance 1e-6 -> black, 1 -> white.
      const float t = std::clamp((std::log10(std::max(rel[p], 1e-6f)) + 6.0f) / 6.0f, 0.0f, 1.0f);
      thumb.rgb[p * 3] = thumb.rgb[p * 3 + 1] = thumb.rgb[p * 3 + 2] = t;
    }
    if (std::string e = writeRgbImage(thumbnail, thumb); !e.empty()) {
      std::fprintf(stderr, "tex develop: error: %s\n", e.c_str());
      return 1;
    }
  }
  if (!quiet) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "tex develop: %llu records (%llu samples, %s) -> %s %dx%d %s filter in %.2f s\n",
                 (unsigned long long)records, (unsigned long long)samples, runtime::formatRanges(ranges).c_str(),
                 output.c_str(), settings.width, settings.height, filterName(settings.filter), seconds);
  }
  return 0;
}

TEX_COMMAND("develop", "develop sample files into an image at any resolution and filter", &runDevelop);

}  // namespace tex::cli
