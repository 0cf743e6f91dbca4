// Stream runtime benchmarks: runtime + film-sink overhead with a trivial kernel (samples/s per
// core), 1 vs 2 threads on a compute-bound kernel (speed-up table printed after the Google
// Benchmark results), and the sample file's write/read throughput and size per sample.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "renderer/film/film_sink.h"
#include "renderer/io/sample_file.h"
#include "renderer/sampling/sampler.h"
#include "runtime/stream.h"

namespace {

using namespace tex;

// The trivial kernel: one scalar record at the Sobol film position of the index.
struct TrivialKernel {
  sampling::Sampler sampler{sampling::SamplerKind::Sobol, 1};
  void operator()(uint64_t index, runtime::Emitter<SampleRecord>& out) const {
    SampleRecord& r = out.emplace();
    const sampling::FilmPosition p = sampler.filmPosition(index);
    r.filmX = p.x, r.filmY = p.y, r.wavelengthCount = 1, r.values[0] = 1.0f;
  }
};

// A compute-bound kernel: 64 Sobol dimensions and some transcendental math per index.
struct ComputeKernel {
  sampling::Sampler sampler{sampling::SamplerKind::Sobol, 2};
  void operator()(uint64_t index, runtime::Emitter<SampleRecord>& out) const {
    SampleRecord& r = out.emplace();
    const sampling::FilmPosition p = sampler.filmPosition(index);
    float acc = 0;
    for (int d = 3; d < 67; ++d) acc += std::sin(6.2831853f * sampler.get(index, d)) * std::exp(-float(d) * 0.01f);
    r.filmX = p.x, r.filmY = p.y, r.wavelengthCount = 1, r.values[0] = acc;
  }
};

template <class Kernel>
double runFilm(int threads, uint64_t samples, int resolution = 256) {
  FilmSettings settings;
  settings.width = settings.height = resolution;
  settings.valueKind = ValueKind::Scalar;
  FilmSink sink(settings);
  runtime::Sink<SampleRecord>* sinks[] = {&sink};
  runtime::SchedulerOptions options;
  options.threads = threads;
  options.chunkSize = 16384;
  const auto start = std::chrono::steady_clock::now();
  runtime::runStream<SampleRecord>({0, samples}, options, Kernel{}, std::span<runtime::Sink<SampleRecord>* const>(sinks));
  benchmark::DoNotOptimize(sink.film().sums().data());
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void BM_TrivialKernelThroughFilmSink(benchmark::State& state) {
  const int threads = int(state.range(0));
  const uint64_t samples = uint64_t(1) << 24;
  for (auto _ : state) state.SetIterationTime(runFilm<TrivialKernel>(threads, samples, int(state.range(1))));
  state.SetItemsProcessed(int64_t(state.iterations() * samples));
  state.counters["samples/s/core"] =
      benchmark::Counter(double(state.iterations() * samples) / threads, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TrivialKernelThroughFilmSink)->Args({1, 64})->Args({1, 256})->Args({1, 1024})->Args({2, 256})->UseManualTime()->Unit(benchmark::kMillisecond);

void BM_ComputeKernel(benchmark::State& state) {
  const int threads = int(state.range(0));
  const uint64_t samples = uint64_t(1) << 21;
  for (auto _ : state) state.SetIterationTime(runFilm<ComputeKernel>(threads, samples));
  state.SetItemsProcessed(int64_t(state.iterations() * samples));
}
BENCHMARK(BM_ComputeKernel)->Arg(1)->Arg(2)->UseManualTime()->Unit(benchmark::kMillisecond);

std::vector<SampleRecord> spectralRecords(size_t n) {
  std::vector<SampleRecord> records(n);
  const sampling::Sampler sampler(sampling::SamplerKind::Sobol, 3);
  for (size_t i = 0; i < n; ++i) {
    SampleRecord& r = records[i];
    const sampling::FilmPosition p = sampler.filmPosition(i);
    r.filmX = p.x, r.filmY = p.y, r.wavelengthCount = 4;
    for (int j = 0; j < 4; ++j) r.lambdaNm[j] = 360 + 470 * sampler.get(i, 2 + j), r.values[j] = sampler.get(i, 10 + j);
  }
  return records;
}

const std::string kBenchFile = (std::filesystem::temp_directory_path() / "tex_bench.samples").string();

// The path tracer's sampler access: 30 Sobol coordinates (dimensions 2-31) of each of 4096
// consecutive indices, through Sampler::get (arg 0) or one IndexSampler per index (arg 1).
// Items are coordinates.
void BM_SobolCoordinatesPerIndex(benchmark::State& state) {
  const sampling::Sampler sampler(sampling::SamplerKind::Sobol, 3);
  const bool perIndexView = state.range(0) == 1;
  uint64_t first = 0;
  for (auto _ : state) {
    float acc = 0.0f;
    for (uint64_t index = first; index < first + 4096; ++index) {
      if (perIndexView) {
        const sampling::IndexSampler samples(sampler, index);
        for (int d = 2; d < 32; ++d) acc += samples.get(d);
      } else {
        for (int d = 2; d < 32; ++d) acc += sampler.get(index, d);
      }
    }
    benchmark::DoNotOptimize(acc);
    first += 4096;
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * 4096 * 30);
}
BENCHMARK(BM_SobolCoordinatesPerIndex)->Arg(0)->Arg(1);

void writeFile(const std::vector<SampleRecord>& records, SampleCompression compression) {
  SampleFileWriter writer;
  SampleFileHeader header;
  header.wavelengthsPerRecord = 4;
  header.compression = compression;
  writer.open(kBenchFile, header);
  const size_t chunk = 16384;
  for (size_t first = 0; first < records.size(); first += chunk) {
    const size_t n = std::min(chunk, records.size() - first);
    writer.writeChunk({first, first + n}, std::span<const SampleRecord>(records.data() + first, n));
  }
  writer.close({{0, records.size()}});
}

void BM_SampleFileWrite(benchmark::State& state) {
  const auto compression = SampleCompression(state.range(0));
  const auto records = spectralRecords(1 << 21);
  for (auto _ : state) writeFile(records, compression);
  const uint64_t bytes = std::filesystem::file_size(kBenchFile);
  state.SetBytesProcessed(int64_t(state.iterations() * bytes));
  state.SetItemsProcessed(int64_t(state.iterations() * records.size()));
  state.counters["bytes/sample"] = double(bytes) / double(records.size());
}
BENCHMARK(BM_SampleFileWrite)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_SampleFileRead(benchmark::State& state) {
  const auto records = spectralRecords(1 << 21);
  writeFile(records, SampleCompression(state.range(0)));
  const uint64_t bytes = std::filesystem::file_size(kBenchFile);
  for (auto _ : state) {
    SampleFileInfo info;
    uint64_t n = 0;
    readSampleFile(kBenchFile, info, [&](runtime::IndexRange, std::span<const SampleRecord> r) { n += r.size(); });
    benchmark::DoNotOptimize(n);
  }
  state.SetBytesProcessed(int64_t(state.iterations() * bytes));
  state.SetItemsProcessed(int64_t(state.iterations() * records.size()));
  state.counters["bytes/sample"] = double(bytes) / double(records.size());
}
BENCHMARK(BM_SampleFileRead)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The scaling tables: best of several runs with 1 and 2 threads, the compute-bound kernel and
// the trivial kernel (runtime + film-sink overhead at 256x256 and 1024x1024).
template <class Kernel>
void printScalingTable(const char* title, uint64_t samples, int resolution, int repetitions) {
  double best[3] = {1e9, 1e9, 1e9};
  for (int rep = 0; rep < repetitions; ++rep)
    for (int t = 1; t <= 2; ++t) best[t] = std::min(best[t], runFilm<Kernel>(t, samples, resolution));
  std::printf("\n%s, %llu samples, film sink %dx%d box (best of %d)\n", title, (unsigned long long)samples, resolution,
              resolution, repetitions);
  std::printf("%8s %12s %14s %18s %10s\n", "threads", "seconds", "M samples/s", "M samples/s/core", "speed-up");
  for (int t = 1; t <= 2; ++t) {
    std::printf("%8d %12.4f %14.2f %18.2f %9.2fx\n", t, best[t], samples / best[t] / 1e6, samples / best[t] / 1e6 / t,
                best[1] / best[t]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  printScalingTable<ComputeKernel>("compute-bound kernel", uint64_t(1) << 21, 256, 3);
  printScalingTable<TrivialKernel>("trivial kernel", uint64_t(1) << 24, 256, 5);
  printScalingTable<TrivialKernel>("trivial kernel", uint64_t(1) << 24, 1024, 5);
  std::filesystem::remove(kBenchFile);
  return 0;
}
