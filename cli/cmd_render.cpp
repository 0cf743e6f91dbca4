// `tex render`: a scene (scene JSON, or a glTF file directly) through the spectral path
// tracer into an OpenEXR or PNG image, with progress, a time budget, Ctrl-C keeping the
// partial image, an optional sample file, and a summary line.
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "cli/command.h"
#include "cli/option_values.h"
#include "lang/image_table.h"
#include "renderer/film/film_sink.h"
#include "renderer/integrators/path_tracer.h"
#include "renderer/lights/image_environment.h"
#include "renderer/integrators/render_scene.h"
#include "renderer/io/sample_file.h"
#include "renderer/sampling/hash.h"
#include "renderer/scene/load_scene.h"
#include "runtime/cancellation.h"
#include "runtime/progress.h"

namespace tex::cli {

namespace {

const char* kRenderUsage =
    "usage: tex render SCENE [options]\n"
    "SCENE is a scene file (.json, docs/scene-format.md) or a glTF 2.0 file (.gltf, .glb).\n"
    "\n"
    "options (flags override the scene file's settings):\n"
    "  -o, --output PATH   image to write: .exr (RGB + variance, metadata) or .png (default render.exr);\n"
    "                      repeat -o to write the same render in several files\n"
    "  --spp N             samples per pixel (default 16)\n"
    "  --time SECONDS      stop starting new work after this long; the image keeps what was done\n"
    "  --threads T         worker threads (default: all cores)\n"
    "  --seed S            sampler seed, 0..2^64-1 (default 0); the same seed gives the same image at any\n"
    "                      thread count\n"
    "  --res WxH           image resolution (default 512x512, or the scene's)\n"
    "  --crop X,Y,W,H      render only this window of the image (pixels; the output is WxH)\n"
    "  --integrator NAME   path (default; the only one so far)\n"
    "  --max-depth N       scattering events per path, 0..1000 (default 8; 0: emitters seen directly)\n"
    "  --roulette-depth N  Russian roulette may end a path after N scattering events, 1..65536 (default 3;\n"
    "                      Mitsuba 3's rr_depth counts the same way)\n"
    "  --wavelengths N     wavelengths per path: 4 or 8 (default 4)\n"
    "  --spectral-mode M   mis | terminate | single: at dispersion keep every wavelength with\n"
    "                      spectral MIS (default), keep only the hero, or trace one per path\n"
    "  --light-sampler S   bvh | power: next-event estimation chooses a light by its estimated\n"
    "                      contribution at the point (default) or by power alone\n"
    "                      (docs/light-sampling.md)\n"
    "  --sampler NAME      sobol | random (default sobol)\n"
    "  --filter NAME       box | tent | gaussian | mitchell (default box)\n"
    "  --camera N          which camera of the scene (default 0; none: frame the scene's bounds)\n"
    "  --samples-out PATH  also write every sample record (develop at any resolution: tex develop)\n"
    "  --no-cache          do not use the JIT's on-disk object cache\n"
    "  -q, --quiet         no progress line\n"
    "Ctrl-C stops cleanly and writes the partial image.\n";

int usage(const std::string& message) {
  std::fprintf(stderr, "tex render: error: %s\n%s", message.c_str(), kRenderUsage);
  return 2;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "tex render: error: %s\n", message.c_str());
  return 1;
}

struct RenderFlags {
  std::string scene, samplesOut, integrator;
  std::vector<std::string> outputs;  // -o may repeat: the same render written to each
  int spp = -1, width = -1, height = -1, maxDepth = -1, rouletteDepth = -1, wavelengths = -1, camera = -1;
  int crop[4] = {-1, -1, -1, -1};  // X, Y, W, H in pixels of the image; X < 0: no crop
  std::optional<uint64_t> seed;  // any 64-bit value, as render.seed in a scene file
  double timeSeconds = 0;
  int threads = 0;
  sampling::SamplerKind sampler = sampling::SamplerKind::Sobol;
  FilterKind filter = FilterKind::Box;
  bool noCache = false, quiet = false;
  render::SpectralMode spectralMode = render::SpectralMode::Mis;
  render::LightSelection lightSelection = render::LightSelection::Bvh;
};

// "X,Y,W,H": four integers, X and Y >= 0, W and H >= 1 (checked against the image later).
bool parseCrop(const std::string& text, int crop[4]) {
  std::string rest = text;
  for (int k = 0; k < 4; ++k) {
    const size_t comma = rest.find(',');
    if ((comma == std::string::npos) != (k == 3)) return false;
    const std::string field = k == 3 ? rest : rest.substr(0, comma);
    if (!parseIntInRange(field, crop[k], k < 2 ? 0 : 1, 1 << 20)) return false;
    if (k < 3) rest = rest.substr(comma + 1);
  }
  return true;
}

// Parses flags; returns 0 to go on, else the exit status.
int parseFlags(const Args& args, RenderFlags& f) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    std::string v;
    const auto value = [&] {
      if (i + 1 >= args.size()) return false;
      v = args[++i];
      return true;
    };
    uint64_t count = 0;
    if (a == "-o" || a == "--output") {
      if (!value()) return usage("-o needs a path");
      f.outputs.push_back(v);
    } else if (a == "--spp") {
      if (!value() || !parseIntInRange(v, f.spp, 1, 1 << 24)) return usage("--spp needs a count 1..16777216, got '" + v + "'");
    } else if (a == "--time") {
      if (!value() || !parseSeconds(v, f.timeSeconds) || f.timeSeconds <= 0) return usage("--time needs positive seconds");
    } else if (a == "--threads") {
      if (!value() || !parseIntInRange(v, f.threads, 1, 1024)) return usage("--threads needs 1..1024");
    } else if (a == "--seed") {
      if (!value() || !parseUnsigned(v, count)) return usage("--seed needs an integer 0.." + std::to_string(UINT64_MAX));
      f.seed = count;
    } else if (a == "--res") {
      if (!value() || !parseResolution(v, f.width, f.height)) return usage("--res needs WxH, e.g. 640x480");
    } else if (a == "--crop") {
      if (!value() || !parseCrop(v, f.crop)) return usage("--crop needs X,Y,W,H in pixels, e.g. 100,50,64,64");
    } else if (a == "--integrator") {
      if (!value()) return usage("--integrator needs a name");
      if (v != "path") return usage("unknown integrator '" + v + "' (available: path)");
      f.integrator = v;
    } else if (a == "--max-depth") {
      if (!value() || !parseIntInRange(v, f.maxDepth, 0, 1000)) return usage("--max-depth needs 0..1000");
    } else if (a == "--roulette-depth") {
      // The scene file's range (render.roulette_depth).
      if (!value() || !parseIntInRange(v, f.rouletteDepth, 1, 1 << 16)) return usage("--roulette-depth needs 1..65536");
    } else if (a == "--wavelengths") {
      if (!value() || (v != "4" && v != "8")) return usage("--wavelengths needs 4 or 8");
      f.wavelengths = std::stoi(v);
    } else if (a == "--spectral-mode") {
      if (!value() || !render::parseSpectralMode(v)) return usage("--spectral-mode needs mis, terminate or single");
      f.spectralMode = *render::parseSpectralMode(v);
    } else if (a == "--light-sampler") {
      if (!value() || !render::parseLightSelection(v)) return usage("--light-sampler needs bvh or power");
      f.lightSelection = *render::parseLightSelection(v);
    } else if (a == "--sampler") {
      if (!value() || !sampling::parseSamplerKind(v)) return usage("--sampler needs sobol or random");
      f.sampler = *sampling::parseSamplerKind(v);
    } else if (a == "--filter") {
      if (!value() || !parseFilterKind(v)) return usage("--filter needs box, tent, gaussian or mitchell");
      f.filter = *parseFilterKind(v);
    } else if (a == "--camera") {
      if (!value() || !parseIntInRange(v, f.camera, 0, 1 << 20)) return usage("--camera needs a camera index");
    } else if (a == "--samples-out") {
      if (!value()) return usage("--samples-out needs a path");
      f.samplesOut = v;
    } else if (a == "--no-cache") {
      f.noCache = true;
    } else if (a == "-q" || a == "--quiet") {
      f.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      return usage("unknown option '" + a + "'");
    } else if (f.scene.empty()) {
      f.scene = a;
    } else {
      return usage("one scene at a time (got '" + f.scene + "' and '" + a + "')");
    }
  }
  if (f.scene.empty()) return usage("which scene? (a .json scene file or a .gltf/.glb model)");
  if (f.outputs.empty()) f.outputs.push_back("render.exr");
  for (const std::string& output : f.outputs) {
    const std::string ext = std::filesystem::path(output).extension().string();
    if (ext != ".exr" && ext != ".png") return usage("output must end in .exr or .png, got '" + output + "'");
  }
  // Two outputs (or the image and the sample file) on one file would overwrite each other.
  std::vector<std::string> targets = f.outputs;
  if (!f.samplesOut.empty()) targets.push_back(f.samplesOut);
  for (size_t i = 0; i < targets.size(); ++i)
    for (size_t j = i + 1; j < targets.size(); ++j) {
      if (samePath(targets[i], targets[j]))
        return usage("'" + targets[i] + "' is given twice as an output (" +
                     (j + 1 == targets.size() && !f.samplesOut.empty() ? "image and sample file" : "two images") + ")");
    }
  for (const std::string& output : targets)
    if (const std::string problem = outputDirectoryProblem(output); !problem.empty()) {
      std::fprintf(stderr, "tex render: error: %s\n", problem.c_str());
      return 1;
    }
  return 0;
}

std::string formatRate(double perSecond) {
  char buf[64];
  if (perSecond >= 1e6)
    std::snprintf(buf, sizeof buf, "%.2f M", perSecond / 1e6);
  else
    std::snprintf(buf, sizeof buf, "%.1f k", perSecond / 1e3);
  return buf;
}

int runRender(const Args& args) {
  if (wantsHelp(args)) {
    std::fputs(kRenderUsage, stdout);
    return 0;
  }
  RenderFlags f;
  if (int status = parseFlags(args, f)) return status;
  // Ctrl-C is caught from here on, scene loading and compiling included: a first Ctrl-C during
  // them lets the render stop at once with the (empty) partial image and exit 130. Installed
  // only before the render, a Ctrl-C while loading was lost in shells that start background
  // jobs with SIGINT ignored, and the whole render ran.
  std::atomic<bool> cancel{false};
  runtime::ScopedSigintCancellation sigint(cancel);

  std::string error;
  std::optional<render::SceneDescription> loaded = render::loadScene(f.scene, error);
  if (!loaded) return fail(error.empty() ? "cannot load '" + f.scene + "'" : error);
  render::SceneDescription& scene = *loaded;
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "tex render: warning: %s\n", w.c_str());

  render::RenderSettings& s = scene.settings;
  if (f.spp > 0) s.spp = f.spp;
  if (f.maxDepth >= 0) s.maxDepth = f.maxDepth;  // unset: -1 (0 is a depth: emitters seen directly)
  if (f.rouletteDepth > 0) s.rouletteDepth = f.rouletteDepth;
  if (f.wavelengths > 0) s.wavelengths = f.wavelengths;
  if (f.seed) s.seed = *f.seed;
  if (f.camera >= 0) s.camera = f.camera;
  if (f.width > 0) {
    s.width = f.width;
    s.height = f.height;
  } else if (!scene.resolutionGiven && s.camera >= 0 && size_t(s.camera) < scene.cameras.size() &&
             scene.cameras[size_t(s.camera)].aspect > 0) {
    s.height = std::max(1, int(std::lround(s.width / scene.cameras[size_t(s.camera)].aspect)));
  }
  // The image's shape sets the projection's aspect: a camera's own aspect only picks the
  // height when no resolution is given, so say when it is overruled.
  if (s.camera >= 0 && size_t(s.camera) < scene.cameras.size()) {
    const float aspect = scene.cameras[size_t(s.camera)].aspect;
    const float imageAspect = float(s.width) / float(s.height);
    if (aspect > 0 && std::fabs(aspect - imageAspect) > 0.01f * aspect)
      std::fprintf(stderr, "tex render: warning: camera %d's aspect %g is overruled by the image's %dx%d (aspect %g)\n",
                   s.camera, double(aspect), s.width, s.height, double(imageAspect));
  }
  if (f.camera >= 0 && size_t(f.camera) >= scene.cameras.size())
    return fail("--camera " + std::to_string(f.camera) + ": the scene has " + std::to_string(scene.cameras.size()) + " camera(s)");
  if (s.wavelengths != 4 && s.wavelengths != 8) return fail("wavelengths per path must be 4 or 8");
  // The film: the whole image, or the crop window of it.
  const bool cropped = f.crop[0] >= 0;
  const int filmX = cropped ? f.crop[0] : 0, filmY = cropped ? f.crop[1] : 0;
  const int filmWidth = cropped ? f.crop[2] : s.width, filmHeight = cropped ? f.crop[3] : s.height;
  if (cropped && (int64_t(filmX) + filmWidth > s.width || int64_t(filmY) + filmHeight > s.height))
    return fail("--crop " + std::to_string(filmX) + "," + std::to_string(filmY) + "," + std::to_string(filmWidth) + "," +
                std::to_string(filmHeight) + " reaches outside the " + std::to_string(s.width) + "x" +
                std::to_string(s.height) + " image");
  if (cropped && !f.samplesOut.empty())
    return fail("--crop and --samples-out cannot be combined (a sample file covers the whole image)");

  render::RenderSceneOptions ro;
  ro.width = s.width;
  ro.height = s.height;
  ro.wavelengths = s.wavelengths;
  ro.useCache = !f.noCache;
  std::unique_ptr<render::RenderScene> rs = render::RenderScene::build(scene, ro, error);
  if (!rs) {
    // Located diagnostics already start with the scene's name (and end with a newline).
    while (!error.empty() && error.back() == '\n') error.pop_back();
    // Diagnostics that say "error:" themselves are printed after "tex render:" alone (they
    // read "tex render: error: p3.json:3:16: error: ..." before).
    if (error.find(": error:") != std::string::npos) {
      std::fprintf(stderr, "tex render: %s\n", (error.rfind(f.scene, 0) == 0 ? error : f.scene + ": " + error).c_str());
      return 1;
    }
    return fail(error.rfind(f.scene, 0) == 0 ? error : f.scene + ": " + error);
  }
  // An output must not overwrite what the scene was read from (a --samples-out named like the
  // .glb, an image named like the environment map): checked before rendering.
  std::vector<std::string> inputs = scene.inputFiles;
  for (const std::string& p : lang::ImageTable::global().paths()) inputs.push_back(p);
  std::vector<std::string> targets = f.outputs;
  if (!f.samplesOut.empty()) targets.push_back(f.samplesOut);
  for (const std::string& target : targets)
    for (const std::string& input : inputs)
      if (std::error_code ec; std::filesystem::equivalent(target, input, ec) && !ec)  // the same file, links too
        return fail("the output '" + target + "' is an input of the scene ('" + input + "'); choose another name");

  for (size_t i = 0; i < scene.lights.size() && i < rs->lights().size(); ++i)
    if (const auto* env = dynamic_cast<const render::ImageEnvironment*>(rs->lights()[i]); env && env->droppedPixels() > 0)
      std::fprintf(stderr, "tex render: warning: %s: %llu pixels are NaN, infinite or negative; they emit nothing\n",
                   scene.lights[i].imagePath.c_str(), (unsigned long long)env->droppedPixels());
  if (rs->addedDefaultLight())
    std::fprintf(stderr, "tex render: note: %s has no lights; lighting it with a uniform white sky of radiance 1\n",
                 f.scene.c_str());
  sampling::PixelGrid grid;
  grid.width = filmWidth;
  grid.height = filmHeight;
  grid.originX = filmX;
  grid.originY = filmY;
  grid.imageWidth = s.width;
  grid.imageHeight = s.height;
  const sampling::Sampler sampler(f.sampler, s.seed, grid);
  render::PathTracerSettings pts;
  pts.maxDepth = s.maxDepth;
  pts.rouletteDepth = s.rouletteDepth;
  pts.wavelengths = s.wavelengths;
  pts.spectralMode = f.spectralMode;
  pts.lightSelection = f.lightSelection;
  pts.filmWidth = s.width;
  pts.filmHeight = s.height;
  pts.crop = {float(filmX) / float(s.width), float(filmY) / float(s.height), float(filmX + filmWidth) / float(s.width),
              float(filmY + filmHeight) / float(s.height)};
  const render::PathTracer tracer(*rs, sampler, pts);

  FilmSettings film;
  film.width = filmWidth;
  film.height = filmHeight;
  film.filter = f.filter;
  film.valueKind = ValueKind::SpectralRadianceOverPdf;
  const runtime::IndexRange range{0, uint64_t(filmWidth) * uint64_t(filmHeight) * uint64_t(s.spp)};

  SampleFileWriter writer;
  std::unique_ptr<SampleFileSink> fileSink;
  const uint64_t sceneHash = sampling::hashWords(std::hash<std::string>{}(std::filesystem::absolute(f.scene).string()),
                                                 uint64_t(s.maxDepth), uint64_t(s.wavelengths));
  if (!f.samplesOut.empty()) {
    SampleFileHeader header;
    header.sceneHash = sceneHash;
    header.seed = s.seed;
    header.requested = range;
    header.valueKind = film.valueKind;
    header.wavelengthsPerRecord = uint8_t(s.wavelengths);
    header.sampler = uint8_t(f.sampler);
    header.integrator = "path";
    header.imageWidth = uint32_t(s.width);
    header.imageHeight = uint32_t(s.height);
    if (std::string e = writer.open(f.samplesOut, header); !e.empty()) return fail(e);
    fileSink = std::make_unique<SampleFileSink>(writer);
  }

  FilmSink filmSink(film);
  std::vector<runtime::Sink<SampleRecord>*> sinks = {&filmSink};
  if (fileSink) sinks.push_back(fileSink.get());
  runtime::SchedulerOptions options;
  options.threads = f.threads;
  options.timeBudgetSeconds = f.timeSeconds;
  options.chunkSize = 4096;
  options.cancel = &cancel;
  runtime::ProgressReporter progress("tex render", range.size(), f.timeSeconds, f.quiet ? nullptr : stderr);
  options.progress = &progress;
  const uint64_t storedTriangles = rs->geometry().storedTriangleCount();
  const std::string distinctTriangles = storedTriangles == rs->geometry().triangleCount()
                                            ? std::string()
                                            : " (" + std::to_string(storedTriangles) + " distinct)";
  if (!f.quiet)
    std::fprintf(stderr, "tex render: %s: %llu triangles%s, %zu lights (%d emissive triangles), %dx%d%s, %d spp, %d wavelengths, max depth %d; scene ready in %.2f s (materials %.1f ms%s)\n",
                 f.scene.c_str(), (unsigned long long)rs->geometry().triangleCount(), distinctTriangles.c_str(), rs->lights().size(),
                 rs->triangleLightCount(), s.width, s.height,
                 cropped ? (" cropped to " + std::to_string(filmWidth) + "x" + std::to_string(filmHeight) + " at " +
                            std::to_string(filmX) + "," + std::to_string(filmY)).c_str()
                         : "",
                 s.spp, s.wavelengths, s.maxDepth, rs->buildSeconds(),
                 rs->materials().compileReport().compileMs, rs->materials().compileReport().cacheHit ? ", cached" : "");
  progress.start();
  const runtime::SchedulerResult result = runtime::runStream<SampleRecord>(
      range, options, tracer, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  progress.finish();
  // A sample file that failed (a full disk) does not cost the image: it is still written, and
  // the run then fails.
  const std::string sampleFileError = fileSink ? fileSink->error() : std::string();

  const render::PathCounters counters = tracer.counters();
  const DevelopedImage image = filmSink.film().develop();
  if (image.unstablePixels > 0)
    std::fprintf(stderr, "tex render: warning: in %llu pixels the %s filter's weights nearly cancel (too few samples for its negative lobes): their values are unreliable\n",
                 (unsigned long long)image.unstablePixels, filterName(f.filter));
  if (image.saturatedPixels > 0)
    std::fprintf(stderr, "tex render: warning: %llu pixels saturated the film (values beyond about 5e11 per pixel, summed over its samples): their values and variances are wrong\n",
                 (unsigned long long)image.saturatedPixels);
  std::map<std::string, std::string> metadata = {
      {"tex.scene", f.scene},
      {"tex.samples", std::to_string(result.samplesDone)},
      {"tex.indexRanges", runtime::formatRanges(result.completed)},
      {"tex.seed", std::to_string(s.seed)},
      {"tex.sampler", sampling::samplerName(f.sampler)},
      {"tex.integrator", "path"},
      {"tex.maxDepth", std::to_string(s.maxDepth)},
      {"tex.rouletteDepth", std::to_string(s.rouletteDepth)},
      {"tex.wavelengths", std::to_string(s.wavelengths)},
      {"tex.spectralMode", render::spectralModeName(f.spectralMode)},
      {"tex.lightSampler", render::lightSelectionName(f.lightSelection)},
      {"tex.filter", filterName(f.filter)},
      {"tex.nonFiniteSamples", std::to_string(counters.nonFiniteSamples)}};
  if (cropped)
    metadata["tex.crop"] = std::to_string(filmX) + "," + std::to_string(filmY) + "," + std::to_string(filmWidth) + "," +
                           std::to_string(filmHeight) + " of " + std::to_string(s.width) + "x" + std::to_string(s.height);
  // Every output is attempted: one that cannot be written does not cost the others.
  std::string written, writeErrors;
  for (const std::string& output : f.outputs) {
    const bool png = std::filesystem::path(output).extension() == ".png";
    const std::string e = png ? writeRgbImage(output, image.rgbImage()) : writeExr(output, image.toExr(true, false, metadata));
    if (!e.empty()) {
      std::fprintf(stderr, "tex render: error: %s\n", e.c_str());
      writeErrors += e;
      continue;
    }
    written += (written.empty() ? "" : ", ") + output;
  }
  if (!sampleFileError.empty()) return fail(sampleFileError + (written.empty() ? "" : " (the image was written: " + written + ")"));
  if (!writeErrors.empty()) return 1;

  const double seconds = std::max(result.seconds, 1e-9);
  std::printf("%s: %llu samples (%.2f spp) in %.2f s, %s samples/s, %s rays/s, %d thread%s%s; %llu NaN/Inf samples zeroed%s -> %s\n",
              f.scene.c_str(), (unsigned long long)result.samplesDone,
              double(result.samplesDone) / double(uint64_t(filmWidth) * uint64_t(filmHeight)), seconds,
              formatRate(double(result.samplesDone) / seconds).c_str(), formatRate(double(counters.rays) / seconds).c_str(),
              result.workerSlots, result.workerSlots == 1 ? "" : "s",
              result.cancelled ? " (interrupted: partial image)" : result.timeBudgetReached ? " (time budget reached)" : "",
              (unsigned long long)counters.nonFiniteSamples,
              counters.materialFailures ? (", " + std::to_string(counters.materialFailures) + " material evaluation failures").c_str() : "",
              written.c_str());
  return result.cancelled ? 130 : 0;  // 128 + SIGINT, as shells report an interrupted command
}

}  // namespace

TEX_COMMAND("render", "render a scene (.json or .gltf/.glb) with the spectral path tracer", &runRender);

}  // namespace tex::cli
