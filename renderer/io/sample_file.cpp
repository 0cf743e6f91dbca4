#include "renderer/io/sample_file.h"

#include <zstd.h>

#include <filesystem>

#include <algorithm>
#include <bit>
#include <cstring>
#include <memory>

namespace tex {

static_assert(std::endian::native == std::endian::little, "the sample file is little-endian; add byte swaps");

namespace {

constexpr char kMagic[8] = {'T', 'E', 'X', 'S', 'A', 'M', 'P', 'L'};
constexpr uint32_t kChunkMagic = 0x4b4e4843;   // "CHNK"
constexpr uint32_t kFooterMagic = 0x444e4554;  // "TEND"
constexpr size_t kHeaderBytes = 128;
constexpr size_t kChunkHeaderBytes = 40;
constexpr uint32_t kMaxRecordsPerChunk = 1u << 24;
constexpr uint64_t kMaxFooterRanges = 1u << 24;

// Header field offsets.
enum : size_t {
  kOffVersion = 8, kOffHeaderBytes = 12, kOffSceneHash = 16, kOffSeed = 24, kOffRequestedBegin = 32,
  kOffRequestedEnd = 40, kOffValueKind = 48, kOffWavelengths = 49, kOffCompression = 50, kOffSampler = 51,
  kOffFooter = 56, kOffIntegrator = 64, kIntegratorBytes = 32, kOffImageWidth = 96, kOffImageHeight = 100,
};

template <class T>
void put(uint8_t* p, T v) { std::memcpy(p, &v, sizeof v); }
template <class T>
T get(const uint8_t* p) { T v; std::memcpy(&v, p, sizeof v); return v; }

size_t bytesPerRecord(int w) { return 4 * 3 + 2 + 1 + 8 * size_t(w); }

struct Column {
  size_t offset, count, elementBytes;
};
// The payload's columns: filmX, filmY, weight (f32), technique (u16), wavelengthCount (u8),
// lambdaNm (f32 x w), values (f32 x w).
std::vector<Column> columns(size_t n, int w) {
  std::vector<Column> c;
  size_t offset = 0;
  auto add = [&](size_t count, size_t bytes) { c.push_back({offset, count, bytes}); offset += count * bytes; };
  add(n, 4), add(n, 4), add(n, 4), add(n, 2), add(n, 1), add(n * w, 4), add(n * w, 4);
  return c;
}

// Byte-plane transposition of fixed-size elements (improves compression of floats).
void shuffle(const uint8_t* in, uint8_t* out, size_t count, size_t bytes) {
  for (size_t i = 0; i < count; ++i)
    for (size_t b = 0; b < bytes; ++b) out[b * count + i] = in[i * bytes + b];
}
void unshuffle(const uint8_t* in, uint8_t* out, size_t count, size_t bytes) {
  for (size_t i = 0; i < count; ++i)
    for (size_t b = 0; b < bytes; ++b) out[i * bytes + b] = in[b * count + i];
}

std::vector<uint8_t> encodeRaw(std::span<const SampleRecord> records, int w) {
  const size_t n = records.size();
  std::vector<uint8_t> raw(n * bytesPerRecord(w));
  const std::vector<Column> c = columns(n, w);
  for (size_t i = 0; i < n; ++i) {
    const SampleRecord& r = records[i];
    put(&raw[c[0].offset + 4 * i], r.filmX);
    put(&raw[c[1].offset + 4 * i], r.filmY);
    put(&raw[c[2].offset + 4 * i], r.weight);
    put(&raw[c[3].offset + 2 * i], r.technique);
    raw[c[4].offset + i] = std::min<uint8_t>(r.wavelengthCount, uint8_t(w));
    std::memcpy(&raw[c[5].offset + 4 * w * i], r.lambdaNm.data(), 4 * size_t(w));
    std::memcpy(&raw[c[6].offset + 4 * w * i], r.values.data(), 4 * size_t(w));
  }
  return raw;
}

void decodeRaw(const uint8_t* raw, size_t n, int w, std::vector<SampleRecord>& out) {
  const std::vector<Column> c = columns(n, w);
  out.assign(n, SampleRecord{});
  for (size_t i = 0; i < n; ++i) {
    SampleRecord& r = out[i];
    r.filmX = get<float>(&raw[c[0].offset + 4 * i]);
    r.filmY = get<float>(&raw[c[1].offset + 4 * i]);
    r.weight = get<float>(&raw[c[2].offset + 4 * i]);
    r.technique = get<uint16_t>(&raw[c[3].offset + 2 * i]);
    r.wavelengthCount = std::min<uint8_t>(raw[c[4].offset + i], uint8_t(w));
    std::memcpy(r.lambdaNm.data(), &raw[c[5].offset + 4 * w * i], 4 * size_t(w));
    std::memcpy(r.values.data(), &raw[c[6].offset + 4 * w * i], 4 * size_t(w));
  }
}

void encodeHeader(const SampleFileHeader& h, uint64_t footerOffset, uint8_t* out) {
  std::memset(out, 0, kHeaderBytes);
  std::memcpy(out, kMagic, 8);
  put<uint32_t>(out + kOffVersion, h.version);
  put<uint32_t>(out + kOffHeaderBytes, uint32_t(kHeaderBytes));
  put<uint64_t>(out + kOffSceneHash, h.sceneHash);
  put<uint64_t>(out + kOffSeed, h.seed);
  put<uint64_t>(out + kOffRequestedBegin, h.requested.begin);
  put<uint64_t>(out + kOffRequestedEnd, h.requested.end);
  out[kOffValueKind] = uint8_t(h.valueKind);
  out[kOffWavelengths] = h.wavelengthsPerRecord;
  out[kOffCompression] = uint8_t(h.compression);
  out[kOffSampler] = h.sampler;
  put<uint64_t>(out + kOffFooter, footerOffset);
  std::memcpy(out + kOffIntegrator, h.integrator.data(), std::min(h.integrator.size(), size_t(kIntegratorBytes - 1)));
  put<uint32_t>(out + kOffImageWidth, h.imageWidth);
  put<uint32_t>(out + kOffImageHeight, h.imageHeight);
}

// Reads exactly `size` bytes; false at end of file.
bool readExact(std::FILE* f, void* data, size_t size) { return size == 0 || std::fread(data, 1, size, f) == size; }

struct FileCloser {
  void operator()(std::FILE* f) const { if (f) std::fclose(f); }
};

}  // namespace

uint64_t sampleChecksum(const uint8_t* data, size_t size) {
  uint64_t h = 0x9e3779b97f4a7c15ull ^ size;
  size_t i = 0;
  for (; i + 8 <= size; i += 8) {
    h = (h ^ get<uint64_t>(data + i)) * 0xff51afd7ed558ccdull;
    h = std::rotl(h, 29);
  }
  uint64_t tail = 0;
  std::memcpy(&tail, data + i, size - i);
  h = (h ^ tail) * 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

// ---- writer ------------------------------------------------------------------------------

SampleFileWriter::~SampleFileWriter() {
  if (file_ != nullptr) std::fclose(file_);
}

std::string SampleFileWriter::open(const std::string& path, const SampleFileHeader& header) {
  path_ = path;
  header_ = header;
  if (header.wavelengthsPerRecord < 1 || header.wavelengthsPerRecord > color::kMaxWavelengths) {
    return path + ": wavelengths per record must be 1..8";
  }
  file_ = std::fopen(path.c_str(), "wb");
  if (file_ == nullptr) return path + ": cannot create sample file: " + std::strerror(errno);
  std::setvbuf(file_, nullptr, _IOFBF, 1 << 20);
  uint8_t bytes[kHeaderBytes];
  encodeHeader(header_, 0, bytes);
  if (std::fwrite(bytes, 1, kHeaderBytes, file_) != kHeaderBytes) return error_ = path + ": write failed";
  bytes_ = kHeaderBytes;
  return "";
}

std::string SampleFileWriter::writeChunk(runtime::IndexRange indices, std::span<const SampleRecord> records) {
  if (file_ == nullptr) return path_ + ": sample file is not open";
  if (records.size() > kMaxRecordsPerChunk) return path_ + ": chunk too large";
  const int w = header_.wavelengthsPerRecord;
  std::vector<uint8_t> raw = encodeRaw(records, w);
  const uint64_t checksum = sampleChecksum(raw.data(), raw.size());
  std::vector<uint8_t> stored;
  const std::vector<uint8_t>* payload = &raw;
  if (header_.compression == SampleCompression::Zstd && !raw.empty()) {
    std::vector<uint8_t> shuffled(raw.size());
    for (const Column& c : columns(records.size(), w)) {
      shuffle(&raw[c.offset], &shuffled[c.offset], c.count, c.elementBytes);
    }
    stored.resize(ZSTD_compressBound(raw.size()));
    const size_t size = ZSTD_compress(stored.data(), stored.size(), shuffled.data(), shuffled.size(), 3);
    if (ZSTD_isError(size)) return path_ + ": zstd: " + ZSTD_getErrorName(size);
    stored.resize(size);
    payload = &stored;
  }
  uint8_t head[kChunkHeaderBytes];
  put<uint32_t>(head + 0, kChunkMagic);
  put<uint32_t>(head + 4, uint32_t(records.size()));
  put<uint64_t>(head + 8, indices.begin);
  put<uint64_t>(head + 16, indices.end);
  put<uint32_t>(head + 24, uint32_t(raw.size()));
  put<uint32_t>(head + 28, uint32_t(payload->size()));
  put<uint64_t>(head + 32, checksum);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!error_.empty()) return error_;
  if (std::fwrite(head, 1, kChunkHeaderBytes, file_) != kChunkHeaderBytes ||
      std::fwrite(payload->data(), 1, payload->size(), file_) != payload->size()) {
    return error_ = path_ + ": write failed (disk full?)";
  }
  bytes_ += kChunkHeaderBytes + payload->size();
  records_ += records.size();
  chunks_ += 1;
  return "";
}

std::string SampleFileWriter::close(const std::vector<runtime::IndexRange>& completed) {
  if (file_ == nullptr) return error_;
  std::lock_guard<std::mutex> lock(mutex_);
  const std::vector<runtime::IndexRange> ranges = runtime::mergeRanges(completed);
  std::vector<uint8_t> footer(24 + 16 * ranges.size() + 8);
  put<uint32_t>(&footer[0], kFooterMagic);
  put<uint32_t>(&footer[4], uint32_t(ranges.size()));
  put<uint64_t>(&footer[8], records_);
  put<uint64_t>(&footer[16], chunks_);
  for (size_t i = 0; i < ranges.size(); ++i) {
    put<uint64_t>(&footer[24 + 16 * i], ranges[i].begin);
    put<uint64_t>(&footer[32 + 16 * i], ranges[i].end);
  }
  put<uint64_t>(&footer[footer.size() - 8], sampleChecksum(footer.data(), footer.size() - 8));
  const uint64_t footerOffset = bytes_;
  bool ok = error_.empty() && std::fwrite(footer.data(), 1, footer.size(), file_) == footer.size();
  uint8_t head[kHeaderBytes];
  encodeHeader(header_, footerOffset, head);
  ok = ok && std::fseek(file_, 0, SEEK_SET) == 0 && std::fwrite(head, 1, kHeaderBytes, file_) == kHeaderBytes;
  ok = (std::fclose(file_) == 0) && ok;
  file_ = nullptr;
  bytes_ += footer.size();
  if (!ok && error_.empty()) error_ = path_ + ": write failed while closing";
  return error_;
}

// ---- reader ------------------------------------------------------------------------------

namespace {

std::string readHeader(std::FILE* f, const std::string& path, SampleFileHeader& h, uint64_t& footerOffset) {
  uint8_t b[kHeaderBytes];
  if (!readExact(f, b, kHeaderBytes)) return path + ": not a tex sample file (shorter than its 128-byte header)";
  if (std::memcmp(b, kMagic, 8) != 0) return path + ": not a tex sample file (bad magic)";
  h.version = get<uint32_t>(b + kOffVersion);
  if (h.version != kSampleFileVersion) {
    return path + ": unsupported sample file version " + std::to_string(h.version) + " (this tex reads version " +
           std::to_string(kSampleFileVersion) + ")";
  }
  if (get<uint32_t>(b + kOffHeaderBytes) != kHeaderBytes) return path + ": corrupt header (header size)";
  h.sceneHash = get<uint64_t>(b + kOffSceneHash);
  h.imageWidth = get<uint32_t>(b + kOffImageWidth);
  h.imageHeight = get<uint32_t>(b + kOffImageHeight);
  h.seed = get<uint64_t>(b + kOffSeed);
  h.requested = {get<uint64_t>(b + kOffRequestedBegin), get<uint64_t>(b + kOffRequestedEnd)};
  if (b[kOffValueKind] > uint8_t(ValueKind::Scalar)) return path + ": corrupt header (value kind)";
  h.valueKind = ValueKind(b[kOffValueKind]);
  h.wavelengthsPerRecord = b[kOffWavelengths];
  if (h.wavelengthsPerRecord < 1 || h.wavelengthsPerRecord > color::kMaxWavelengths) {
    return path + ": corrupt header (wavelengths per record " + std::to_string(h.wavelengthsPerRecord) + ")";
  }
  if (b[kOffCompression] > uint8_t(SampleCompression::Zstd)) return path + ": corrupt header (compression)";
  h.compression = SampleCompression(b[kOffCompression]);
  h.sampler = b[kOffSampler];
  footerOffset = get<uint64_t>(b + kOffFooter);
  const char* name = reinterpret_cast<const char*>(b + kOffIntegrator);
  h.integrator.assign(name, strnlen(name, kIntegratorBytes - 1));
  return "";
}

std::string readFooter(std::FILE* f, const std::string& path, uint64_t footerOffset, uint64_t fileBytes,
                       SampleFileInfo& info) {
  if (footerOffset < kHeaderBytes || footerOffset + 32 > fileBytes) return path + ": corrupt file (footer offset)";
  if (std::fseek(f, long(footerOffset), SEEK_SET) != 0) return path + ": cannot seek to footer";
  uint8_t head[24];
  if (!readExact(f, head, 24) || get<uint32_t>(head) != kFooterMagic) return path + ": corrupt file (footer magic)";
  const uint64_t rangeCount = get<uint32_t>(head + 4);
  if (rangeCount > kMaxFooterRanges || footerOffset + 24 + 16 * rangeCount + 8 != fileBytes) {
    return path + ": corrupt file (footer size)";
  }
  std::vector<uint8_t> footer(24 + 16 * rangeCount + 8);
  std::memcpy(footer.data(), head, 24);
  if (!readExact(f, footer.data() + 24, footer.size() - 24)) return path + ": truncated footer";
  if (get<uint64_t>(&footer[footer.size() - 8]) != sampleChecksum(footer.data(), footer.size() - 8)) {
    return path + ": corrupt file (footer checksum)";
  }
  info.records = get<uint64_t>(&footer[8]);
  info.chunks = get<uint64_t>(&footer[16]);
  info.ranges.clear();
  for (uint64_t i = 0; i < rangeCount; ++i) {
    info.ranges.push_back({get<uint64_t>(&footer[24 + 16 * i]), get<uint64_t>(&footer[32 + 16 * i])});
  }
  return "";
}

}  // namespace

std::string readSampleFileInfo(const std::string& path, SampleFileInfo& info) {
  return readSampleFile(path, info, nullptr);
}

std::string readSampleFile(const std::string& path, SampleFileInfo& info,
                           const std::function<void(runtime::IndexRange, std::span<const SampleRecord>)>& onChunk) {
  info = SampleFileInfo{};
  // Only regular files: fopen of a FIFO blocks until a writer appears (develop hung on one).
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    return path + ": not a regular file";
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) return path + ": cannot open sample file: " + std::strerror(errno);
  std::FILE* f = file.get();
  std::setvbuf(f, nullptr, _IOFBF, 1 << 20);
  if (std::fseek(f, 0, SEEK_END) != 0) return path + ": cannot seek (not a regular file?)";
  const long end = std::ftell(f);
  if (end < 0) return path + ": cannot determine file size";
  info.fileBytes = uint64_t(end);
  std::rewind(f);
  uint64_t footerOffset = 0;
  if (std::string e = readHeader(f, path, info.header, footerOffset); !e.empty()) return e;
  info.complete = footerOffset != 0;
  SampleFileInfo footerInfo;
  if (info.complete) {
    if (std::string e = readFooter(f, path, footerOffset, info.fileBytes, footerInfo); !e.empty()) return e;
    if (!onChunk) {
      info.ranges = footerInfo.ranges, info.records = footerInfo.records, info.chunks = footerInfo.chunks;
      return "";
    }
    if (std::fseek(f, long(kHeaderBytes), SEEK_SET) != 0) return path + ": cannot seek to the first chunk";
  }
  const uint64_t chunksEnd = info.complete ? footerOffset : info.fileBytes;
  const int w = info.header.wavelengthsPerRecord;
  std::vector<runtime::IndexRange> chunkRanges;
  std::vector<uint8_t> stored, raw, shuffled;
  std::vector<SampleRecord> records;
  uint64_t offset = kHeaderBytes;
  while (offset < chunksEnd) {
    const std::string where = path + ": chunk " + std::to_string(info.chunks) + " at byte " + std::to_string(offset);
    uint8_t head[kChunkHeaderBytes];
    if (offset + kChunkHeaderBytes > chunksEnd || !readExact(f, head, kChunkHeaderBytes)) {
      if (!info.complete) break;  // a killed writer's partial chunk: keep what came before
      return where + ": truncated chunk header";
    }
    const uint32_t n = get<uint32_t>(head + 4);
    const runtime::IndexRange indices{get<uint64_t>(head + 8), get<uint64_t>(head + 16)};
    const uint32_t rawBytes = get<uint32_t>(head + 24), storedBytes = get<uint32_t>(head + 28);
    const uint64_t checksum = get<uint64_t>(head + 32);
    if (get<uint32_t>(head) != kChunkMagic) {
      if (!info.complete) break;
      return where + ": corrupt chunk (bad magic)";
    }
    if (n > kMaxRecordsPerChunk || rawBytes != n * bytesPerRecord(w) || indices.end < indices.begin ||
        (info.header.compression == SampleCompression::None && storedBytes != rawBytes) ||
        storedBytes > ZSTD_compressBound(rawBytes)) {
      return where + ": corrupt chunk header";
    }
    if (offset + kChunkHeaderBytes + storedBytes > chunksEnd) {
      if (!info.complete) break;
      return where + ": truncated chunk payload";
    }
    stored.resize(storedBytes);
    if (!readExact(f, stored.data(), storedBytes)) {
      if (!info.complete) break;
      return where + ": truncated chunk payload";
    }
    const uint8_t* rawData = stored.data();
    if (info.header.compression == SampleCompression::Zstd && rawBytes > 0) {
      // The frame records its content size: a header claiming 2^24 records in a tiny payload
      // must not allocate 1.3 GB before the payload is found corrupt.
      const unsigned long long frameBytes = ZSTD_getFrameContentSize(stored.data(), storedBytes);
      if (frameBytes != rawBytes) return where + ": corrupt compressed payload";
      shuffled.resize(rawBytes);
      const size_t size = ZSTD_decompress(shuffled.data(), rawBytes, stored.data(), storedBytes);
      if (ZSTD_isError(size) || size != rawBytes) return where + ": corrupt compressed payload";
      raw.resize(rawBytes);
      for (const Column& c : columns(n, w)) unshuffle(&shuffled[c.offset], &raw[c.offset], c.count, c.elementBytes);
      rawData = raw.data();
    }
    if (sampleChecksum(rawData, rawBytes) != checksum) return where + ": checksum mismatch (file damaged)";
    decodeRaw(rawData, n, w, records);
    if (onChunk) onChunk(indices, std::span<const SampleRecord>(records));
    chunkRanges.push_back(indices);
    info.records += n;
    info.chunks += 1;
    offset += kChunkHeaderBytes + storedBytes;
  }
  if (runtime::rangesOverlap(chunkRanges)) return path + ": corrupt file (chunks with overlapping index ranges)";
  info.ranges = runtime::mergeRanges(chunkRanges);
  if (info.complete && (info.ranges != runtime::mergeRanges(footerInfo.ranges) || info.records != footerInfo.records ||
                        info.chunks != footerInfo.chunks)) {
    return path + ": corrupt file (footer does not match the chunks)";
  }
  return "";
}

// ---- sink --------------------------------------------------------------------------------

void SampleFileSink::consume(int, const runtime::ChunkRecords<SampleRecord>& chunk) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_.empty()) return;
  }
  std::string e = writer_.writeChunk(chunk.indices, chunk.records);
  if (!e.empty()) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (error_.empty()) error_ = e;
  }
}

void SampleFileSink::end(const runtime::SchedulerResult& result) {
  std::string e = writer_.close(result.completed);
  if (!e.empty() && error_.empty()) error_ = e;
}

}  // namespace tex
