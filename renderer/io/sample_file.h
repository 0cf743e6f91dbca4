// The sample file: a stream of sample records on disk (the image as a continuous function).
// Format (docs/sample-file.md): a 128-byte header, then chunks (one per runtime chunk, in
// completion order, each with its index range, column-wise payload, optional zstd, and a
// checksum), then a footer with the completed index ranges. Written while rendering, so a
// stopped run keeps every delivered chunk; a file without footer (killed writer) can still
// be read up to its last whole chunk.
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "renderer/film/sample_record.h"
#include "runtime/index_range.h"
#include "runtime/stream.h"

namespace tex {

inline constexpr uint32_t kSampleFileVersion = 1;

enum class SampleCompression : uint8_t { None = 0, Zstd = 1 };

struct SampleFileHeader {
  uint32_t version = kSampleFileVersion;
  uint64_t sceneHash = 0;             // identifies what was rendered (files must match to merge)
  uint64_t seed = 0;                  // the sampler seed
  runtime::IndexRange requested;      // the range the run was asked for
  ValueKind valueKind = ValueKind::SpectralRadianceOverPdf;
  uint8_t wavelengthsPerRecord = 4;   // 1..8 stored per record
  SampleCompression compression = SampleCompression::None;
  uint8_t sampler = 0;                // sampling::SamplerKind
  std::string integrator;             // at most 31 bytes are stored
  // The render's image size, for tex develop's default resolution (0: not recorded; files
  // written before it was, or kernels without an image).
  uint32_t imageWidth = 0, imageHeight = 0;
};

// What a reader learns from the whole file.
struct SampleFileInfo {
  SampleFileHeader header;
  std::vector<runtime::IndexRange> ranges;  // index ranges the records cover (merged)
  uint64_t records = 0;
  uint64_t chunks = 0;
  uint64_t fileBytes = 0;
  bool complete = true;  // false: no footer (the writer was killed); chunks up to the damage are kept
};

// Thread-safe writer: chunks are encoded (and compressed) by the calling thread; only the
// write itself is serialised.
class SampleFileWriter {
 public:
  SampleFileWriter() = default;
  ~SampleFileWriter();
  SampleFileWriter(const SampleFileWriter&) = delete;
  SampleFileWriter& operator=(const SampleFileWriter&) = delete;

  std::string open(const std::string& path, const SampleFileHeader& header);
  std::string writeChunk(runtime::IndexRange indices, std::span<const SampleRecord> records);
  // Writes the footer with the completed ranges and patches the header; closes the file.
  std::string close(const std::vector<runtime::IndexRange>& completed);

  uint64_t bytesWritten() const { return bytes_; }

 private:
  std::string path_;
  SampleFileHeader header_;
  std::FILE* file_ = nullptr;
  std::mutex mutex_;
  uint64_t bytes_ = 0, records_ = 0, chunks_ = 0;
  std::string error_;
};

// Reads a whole file; onChunk(indices, records) for every chunk in file order. Returns an
// error naming the file and the problem (bad magic, unsupported version, checksum mismatch,
// truncation inside the footer, ...); never throws or crashes on bad input.
std::string readSampleFile(const std::string& path, SampleFileInfo& info,
                           const std::function<void(runtime::IndexRange, std::span<const SampleRecord>)>& onChunk);

// Header and footer only (chunks are skipped, not decoded).
std::string readSampleFileInfo(const std::string& path, SampleFileInfo& info);

// The runtime sink that writes a sample file.
class SampleFileSink : public runtime::Sink<SampleRecord> {
 public:
  explicit SampleFileSink(SampleFileWriter& writer) : writer_(writer) {}
  void consume(int slot, const runtime::ChunkRecords<SampleRecord>& chunk) override;
  void end(const runtime::SchedulerResult& result) override;
  // The first error met (writing stops after it), or empty.
  const std::string& error() const { return error_; }

 private:
  SampleFileWriter& writer_;
  std::mutex mutex_;
  std::string error_;
};

// A 64-bit checksum of a byte buffer (word-wise multiply-rotate; not cryptographic).
uint64_t sampleChecksum(const uint8_t* data, size_t size);

}  // namespace tex
