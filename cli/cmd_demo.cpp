// `tex demo`: the analytic kernel through the whole stream runtime (sampler -> kernel ->
// film and sample-file sinks), and the convergence table that the tests assert.
#include <atomic>
#include <cmath>
#include <cstdio>

#include "cli/command.h"
#include "cli/option_values.h"
#include "renderer/analytic/analytic_kernel.h"
#include "renderer/film/film_sink.h"
#include "renderer/io/sample_file.h"
#include "renderer/sampling/hash.h"
#include "runtime/cancellation.h"
#include "runtime/progress.h"

namespace tex::cli {

namespace {

const char* kDemoUsage =
    "usage: tex demo analytic [options]      render a known image with the stream runtime\n"
    "       tex demo convergence [options]   error against the exact image for growing N\n"
    "\n"
    "analytic options:\n"
    "  --image NAME        disk | checkerboard | gaussian | step (default gaussian)\n"
    "  --sampler NAME      sobol | random (default sobol)\n"
    "  --samples N         sample indices [0, N) (default 4M; suffixes k, M, G, or 2^k)\n"
    "  --range A:B         sample indices [A, B) instead (e.g. one machine's share)\n"
    "  --time SECONDS      stop starting chunks after this long (Ctrl-C also stops cleanly)\n"
    "  --threads T         worker threads (default: all)\n"
    "  --chunk N           samples per chunk (default 16384)\n"
    "  --seed S            sampler seed (default 1)\n"
    "  --spectral [N]      emit spectral records with N wavelengths (4 or 8; default scalar)\n"
    "  --res WxH           film resolution (default 256x256)\n"
    "  --filter NAME       box | tent | gaussian | mitchell (default box)\n"
    "  -o PATH             write the image (.exr with variance channels, or .png)\n"
    "  --samples-out PATH  write the sample file (develop it later with tex develop)\n"
    "  --compress          zstd-compress the sample file\n"
    "  -q, --quiet         no progress\n"
    "\n"
    "convergence options:\n"
    "  --image NAME|all    (default all)   --res WxH (default 16x16)   --max-log2 K (12..28, default 20)\n";

int usage(const std::string& message) {
  std::fprintf(stderr, "tex demo: error: %s\n%s", message.c_str(), kDemoUsage);
  return 2;
}

struct AnalyticRun {
  FilmAccumulator film;
  runtime::SchedulerResult result;
};

// Runs the analytic kernel over `range` into a film (and a sample file if writer != null).
AnalyticRun runAnalytic(const AnalyticKernel& kernel, runtime::IndexRange range, const FilmSettings& settings,
                        runtime::SchedulerOptions options, SampleFileWriter* writer, std::string& error) {
  FilmSink filmSink(settings);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&filmSink};
  std::unique_ptr<SampleFileSink> fileSink;
  if (writer != nullptr) {
    fileSink = std::make_unique<SampleFileSink>(*writer);
    sinks.push_back(fileSink.get());
  }
  AnalyticRun run{FilmAccumulator(settings), {}};
  run.result = runtime::runStream<SampleRecord>(range, options, kernel, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  run.film.merge(filmSink.film());
  if (fileSink) error = fileSink->error();
  return run;
}

double rmseAgainstExact(const DevelopedImage& image, AnalyticImage which) {
  const std::vector<double> exact = exactPixelAverages(which, image.width, image.height);
  double sum = 0;
  for (size_t p = 0; p < exact.size(); ++p)
    for (int k = 0; k < 3; ++k) sum += std::pow(image.rgb[p * 3 + k] - exact[p], 2);
  return std::sqrt(sum / (3.0 * double(exact.size())));
}

int runAnalyticDemo(const Args& args) {
  AnalyticImage image = AnalyticImage::Gaussian;
  sampling::SamplerKind samplerKind = sampling::SamplerKind::Sobol;
  runtime::IndexRange range{0, 4000000};
  uint64_t seed = 1;
  int wavelengths = 0;
  FilmSettings settings;
  settings.width = settings.height = 256;
  runtime::SchedulerOptions options;
  std::string output, samplesOut;
  bool compress = false, quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string v;
    auto value = [&] {
      if (i + 1 >= args.size()) return false;
      v = args[++i];
      return true;
    };
    uint64_t count = 0;
    if (a == "--image") {
      if (!value() || !parseAnalyticImage(v)) return usage("--image needs disk, checkerboard, gaussian or step");
      image = *parseAnalyticImage(v);
    } else if (a == "--sampler") {
      if (!value() || !sampling::parseSamplerKind(v)) return usage("--sampler needs sobol or random");
      samplerKind = *sampling::parseSamplerKind(v);
    } else if (a == "--samples") {
      if (!value() || !parseCount(v, count)) return usage("--samples needs a count, e.g. 4M");
      range = {0, count};
    } else if (a == "--range") {
      if (!value() || !parseIndexRange(v, range)) return usage("--range needs A:B with A <= B");
    } else if (a == "--time") {
      // As tex render: 0 is refused (it meant "no budget" here and ran the whole range).
      if (!value() || !parseSeconds(v, options.timeBudgetSeconds) || options.timeBudgetSeconds <= 0)
        return usage("--time needs positive seconds");
    } else if (a == "--threads") {
      if (!value() || !parseIntInRange(v, options.threads, 1, 1024)) return usage("--threads needs 1..1024");
    } else if (a == "--chunk") {
      if (!value() || !parseCount(v, count) || count == 0) return usage("--chunk needs a positive count");
      options.chunkSize = count;
    } else if (a == "--seed") {
      // Exactly (parseCount goes through a double: 2^53 + 1 became 2^53).
      if (!value() || !parseUnsigned(v, seed)) return usage("--seed needs a non-negative integer");
    } else if (a == "--spectral") {
      wavelengths = 4;
      if (i + 1 < args.size() && (args[i + 1] == "4" || args[i + 1] == "8")) wavelengths = std::stoi(args[++i]);
    } else if (a == "--res") {
      if (!value() || !parseResolution(v, settings.width, settings.height)) return usage("--res needs WxH");
    } else if (a == "--filter") {
      if (!value() || !parseFilterKind(v)) return usage("--filter needs box, tent, gaussian or mitchell");
      settings.filter = *parseFilterKind(v);
    } else if (a == "-o" || a == "--output") {
      if (!value()) return usage("-o needs a path");
      output = v;
    } else if (a == "--samples-out") {
      if (!value()) return usage("--samples-out needs a path");
      samplesOut = v;
    } else if (a == "--compress") {
      compress = true;
    } else if (a == "-q" || a == "--quiet") {
      quiet = true;
    } else {
      return usage("unknown option '" + a + "'");
    }
  }
  // Outputs are checked before the run, as tex render does.
  if (!output.empty()) {
    const std::string ext = std::filesystem::path(output).extension().string();
    if (ext != ".exr" && ext != ".png") return usage("output must end in .exr or .png, got '" + output + "'");
  }
  // The image and the sample file on one path: the image overwrote the samples (as tex render
  // refuses).
  if (!output.empty() && !samplesOut.empty() && samePath(output, samplesOut))
    return usage("'" + output + "' is given twice as an output (image and sample file)");
  for (const std::string& path : {output, samplesOut})
    if (!path.empty())
      if (const std::string problem = outputDirectoryProblem(path); !problem.empty()) {
        std::fprintf(stderr, "tex demo: error: %s\n", problem.c_str());
        return 1;
      }
  settings.valueKind = wavelengths > 0 ? ValueKind::SpectralRadianceOverPdf : ValueKind::Scalar;
  const AnalyticKernel kernel{sampling::Sampler(samplerKind, seed), image, settings.valueKind, std::max(1, wavelengths)};

  SampleFileWriter writer;
  if (!samplesOut.empty()) {
    SampleFileHeader header;
    header.sceneHash = sampling::hashWords(0x616e616c79746963ull, uint64_t(image), uint64_t(settings.valueKind));
    header.seed = seed;
    header.requested = range;
    header.valueKind = settings.valueKind;
    header.wavelengthsPerRecord = uint8_t(std::max(1, wavelengths));
    header.compression = compress ? SampleCompression::Zstd : SampleCompression::None;
    header.sampler = uint8_t(samplerKind);
    header.integrator = std::string("analytic-") + analyticImageName(image);
    header.imageWidth = uint32_t(settings.width);
    header.imageHeight = uint32_t(settings.height);
    if (std::string e = writer.open(samplesOut, header); !e.empty()) {
      std::fprintf(stderr, "tex demo: error: %s\n", e.c_str());
      return 1;
    }
  }
  std::atomic<bool> cancel{false};
  runtime::ScopedSigintCancellation sigint(cancel);
  runtime::ProgressReporter progress("tex demo", range.size(), options.timeBudgetSeconds, quiet ? nullptr : stderr);
  options.cancel = &cancel;
  options.progress = &progress;
  progress.start();
  std::string error;
  AnalyticRun run = runAnalytic(kernel, range, settings, options, samplesOut.empty() ? nullptr : &writer, error);
  progress.finish();
  if (!error.empty()) {
    std::fprintf(stderr, "tex demo: error: %s\n", error.c_str());
    return 1;
  }
  const DevelopedImage developed = run.film.develop();
  const double rmse = rmseAgainstExact(developed, image);
  std::printf("%s, %s sampler, %llu samples in %.3f s (%.1f M samples/s, %d threads)%s: rmse vs exact %.6g\n",
              analyticImageName(image), sampling::samplerName(samplerKind), (unsigned long long)run.result.samplesDone,
              run.result.seconds, run.result.samplesDone / std::max(1e-9, run.result.seconds) / 1e6,
              run.result.workerSlots, run.result.cancelled ? " (interrupted)" : run.result.timeBudgetReached ? " (time budget)" : "",
              rmse);
  std::printf("index ranges done: %s\n", runtime::formatRanges(run.result.completed).c_str());
  if (!samplesOut.empty()) {
    std::printf("sample file %s: %llu bytes, %.2f bytes per sample\n", samplesOut.c_str(),
                (unsigned long long)writer.bytesWritten(),
                double(writer.bytesWritten()) / double(std::max<uint64_t>(1, run.result.samplesDone)));
  }
  if (!output.empty()) {
    const std::map<std::string, std::string> metadata = {
        {"tex.samples", std::to_string(run.result.samplesDone)},
        {"tex.indexRanges", runtime::formatRanges(run.result.completed)},
        {"tex.seed", std::to_string(seed)},
        {"tex.sampler", sampling::samplerName(samplerKind)},
        {"tex.integrator", std::string("analytic-") + analyticImageName(image)},
        {"tex.renderSeconds", std::to_string(run.result.seconds)},
        {"tex.filter", filterName(settings.filter)}};
    const bool png = output.size() >= 4 && output.substr(output.size() - 4) == ".png";
    const std::string e = png ? writeRgbImage(output, developed.rgbImage())
                              : writeExr(output, developed.toExr(true, false, metadata));
    if (!e.empty()) {
      std::fprintf(stderr, "tex demo: error: %s\n", e.c_str());
      return 1;
    }
  }
  return run.result.cancelled ? 130 : 0;  // as tex render: 128 + SIGINT
}

int runConvergenceDemo(const Args& args) {
  std::vector<AnalyticImage> images(std::begin(kAllAnalyticImages), std::end(kAllAnalyticImages));
  FilmSettings settings;
  settings.width = settings.height = 16;
  settings.valueKind = ValueKind::Scalar;
  int maxLog2 = 20;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool hasValue = i + 1 < args.size();
    if (a == "--image" && hasValue) {
      const std::string v = args[++i];
      if (v == "all") continue;
      if (!parseAnalyticImage(v)) return usage("--image needs disk, checkerboard, gaussian, step or all");
      images = {*parseAnalyticImage(v)};
    } else if (a == "--res" && hasValue) {
      if (!parseResolution(args[++i], settings.width, settings.height)) return usage("--res needs WxH");
    } else if (a == "--max-log2" && hasValue) {
      // Sample counts 2^10, 2^12, ... up to 2^K: the slope needs two of them (K = 10 or 11 had
      // fitted one point and printed a slope of nan).
      if (!parseIntInRange(args[++i], maxLog2, 12, 28)) return usage("--max-log2 needs 12..28 (two sample counts or more for a slope)");
    } else {
      return usage("unknown or incomplete option '" + a + "'");
    }
  }
  runtime::SchedulerOptions options;
  for (AnalyticImage image : images) {
    std::printf("%s (%dx%d, box filter): rmse against the exact image\n%10s %14s %14s\n", analyticImageName(image),
                settings.width, settings.height, "N", "sobol", "random");
    std::vector<double> logN, logErr[2];
    for (int k = 10; k <= maxLog2; k += 2) {
      double errors[2];
      for (int s = 0; s < 2; ++s) {
        const AnalyticKernel kernel{sampling::Sampler(s == 0 ? sampling::SamplerKind::Sobol : sampling::SamplerKind::Random, 7),
                                    image, ValueKind::Scalar};
        std::string error;
        AnalyticRun run = runAnalytic(kernel, {0, uint64_t(1) << k}, settings, options, nullptr, error);
        errors[s] = rmseAgainstExact(run.film.develop(), image);
        logErr[s].push_back(std::log(std::max(errors[s], 1e-300)));
      }
      logN.push_back(k * std::log(2.0));
      std::printf("%10llu %14.6g %14.6g\n", 1ull << k, errors[0], errors[1]);
    }
    double slopes[2];
    for (int s = 0; s < 2; ++s) {
      const double n = double(logN.size());
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (size_t i = 0; i < logN.size(); ++i)
        sx += logN[i], sy += logErr[s][i], sxx += logN[i] * logN[i], sxy += logN[i] * logErr[s][i];
      slopes[s] = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    }
    std::printf("%10s %14.3f %14.3f   (fitted log-log slope)\n\n", "slope", slopes[0], slopes[1]);
  }
  return 0;
}

}  // namespace

int runDemo(const Args& args) {
  if (args.empty()) return usage("which demo? (analytic or convergence)");
  if (wantsHelp(args)) {
    std::fputs(kDemoUsage, stdout);
    return 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "analytic") return runAnalyticDemo(rest);
  if (args[0] == "convergence") return runConvergenceDemo(rest);
  return usage("unknown demo '" + args[0] + "'");
}

TEX_COMMAND("demo", "run the analytic kernel through the stream runtime (convergence demo)", &runDemo);

}  // namespace tex::cli
