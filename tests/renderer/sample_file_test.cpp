// The sample file: records round-trip bit for bit (with and without zstd), the header and
// index ranges survive, damaged files are refused with a message naming the file, and a file
// whose writer was killed is still readable up to its last whole chunk.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <sys/stat.h>

#include "renderer/io/sample_file.h"
#include "renderer/sampling/pcg.h"

namespace tex {
namespace {

using runtime::IndexRange;

// The process's peak resident memory (Linux /proc/self/status VmHWM), in kB.
long peakResidentKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6));
  return 0;
}

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("tex_sample_file_" + name)).string();
}

std::vector<SampleRecord> makeRecords(uint64_t first, size_t n, int w) {
  std::vector<SampleRecord> records(n);
  for (size_t i = 0; i < n; ++i) {
    SampleRecord& r = records[i];
    const uint64_t index = first + i;
    r.filmX = sampling::randomUniform(1, index, 0);
    r.filmY = sampling::randomUniform(1, index, 1);
    r.weight = i % 5 == 0 ? 0.5f : 1.0f;
    r.technique = uint16_t(i % 3);
    r.wavelengthCount = uint8_t(w);
    for (int j = 0; j < w; ++j) {
      r.lambdaNm[j] = 360.0f + 470.0f * sampling::randomUniform(1, index, 2 + j);
      r.values[j] = sampling::randomUniform(1, index, 20 + j) * 100.0f;
    }
  }
  records[1].values[0] = std::numeric_limits<float>::quiet_NaN();  // stored as bits, whatever they are
  records[2].values[0] = -0.0f;
  return records;
}

bool sameBits(const SampleRecord& a, const SampleRecord& b, int w) {
  return std::memcmp(&a.filmX, &b.filmX, 4) == 0 && std::memcmp(&a.filmY, &b.filmY, 4) == 0 &&
         std::memcmp(&a.weight, &b.weight, 4) == 0 && a.technique == b.technique &&
         a.wavelengthCount == b.wavelengthCount && std::memcmp(a.lambdaNm.data(), b.lambdaNm.data(), 4 * w) == 0 &&
         std::memcmp(a.values.data(), b.values.data(), 4 * w) == 0;
}

std::string writeFile(const std::string& path, SampleCompression compression, int w, bool close = true) {
  SampleFileWriter writer;
  SampleFileHeader header;
  header.sceneHash = 0xabcdef;
  header.seed = 77;
  header.requested = {100, 400};
  header.wavelengthsPerRecord = uint8_t(w);
  header.compression = compression;
  header.integrator = "analytic";
  header.imageWidth = 640;
  header.imageHeight = 360;
  if (std::string e = writer.open(path, header); !e.empty()) return e;
  // Chunks arrive out of order, as from worker threads.
  for (uint64_t first : {200ull, 100ull, 300ull}) {
    const auto records = makeRecords(first, 100, w);
    if (std::string e = writer.writeChunk({first, first + 100}, records); !e.empty()) return e;
  }
  if (close) return writer.close({{100, 400}});
  return "";
}

TEST(SampleFile, RoundTripIsLosslessWithAndWithoutCompression) {
  for (SampleCompression compression : {SampleCompression::None, SampleCompression::Zstd}) {
    for (int w : {1, 4, 8}) {
      const std::string path = tempPath("rt.samples");
      ASSERT_EQ(writeFile(path, compression, w), "");
      SampleFileInfo info;
      size_t chunks = 0;
      ASSERT_EQ(readSampleFile(path, info,
                               [&](IndexRange indices, std::span<const SampleRecord> records) {
                                 const auto expected = makeRecords(indices.begin, 100, w);
                                 ASSERT_EQ(records.size(), expected.size());
                                 for (size_t i = 0; i < records.size(); ++i) ASSERT_TRUE(sameBits(records[i], expected[i], w)) << i;
                                 ++chunks;
                               }),
                "");
      EXPECT_EQ(chunks, 3u);
      EXPECT_TRUE(info.complete);
      EXPECT_EQ(info.records, 300u);
      EXPECT_EQ(info.ranges, (std::vector<IndexRange>{{100, 400}}));
      EXPECT_EQ(info.header.sceneHash, 0xabcdefu);
      EXPECT_EQ(info.header.seed, 77u);
      EXPECT_EQ(info.header.requested, (IndexRange{100, 400}));
      EXPECT_EQ(info.header.integrator, "analytic");
      EXPECT_EQ(info.header.imageWidth, 640u);  // the render's size, for develop's default
      EXPECT_EQ(info.header.imageHeight, 360u);
      EXPECT_EQ(info.header.wavelengthsPerRecord, w);
      SampleFileInfo quick;
      ASSERT_EQ(readSampleFileInfo(path, quick), "");
      EXPECT_EQ(quick.records, 300u);
      // Uncompressed size is exactly header + chunks + footer.
      if (compression == SampleCompression::None) {
        EXPECT_EQ(info.fileBytes, 128u + 3 * (40 + 100 * (15 + 8 * uint64_t(w))) + 24 + 16 + 8);
      }
      std::filesystem::remove(path);
    }
  }
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}
std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(SampleFile, DamagedFilesAreRefusedWithTheFileName) {
  const std::string path = tempPath("bad.samples");
  SampleFileInfo info;
  auto expectError = [&](const std::string& what) {
    const std::string e = readSampleFile(path, info, [](IndexRange, std::span<const SampleRecord>) {});
    EXPECT_NE(e.find(path), std::string::npos) << what << ": " << e;
    EXPECT_NE(e, "") << what;
  };
  writeBytes(path, "garbage");
  expectError("garbage");
  EXPECT_NE(readSampleFile(tempPath("missing.samples"), info, nullptr), "");

  ASSERT_EQ(writeFile(path, SampleCompression::Zstd, 4), "");
  const std::string good = readBytes(path);
  std::string bytes = good;
  bytes[8] = 9;  // version
  writeBytes(path, bytes);
  expectError("version");
  bytes = good;
  bytes[49] = 12;  // wavelengths per record
  writeBytes(path, bytes);
  expectError("wavelengths");
  bytes = good;
  bytes[128 + 40 + 30] ^= 0x55;  // inside the first compressed payload
  writeBytes(path, bytes);
  expectError("payload");
  bytes = good;
  bytes.resize(bytes.size() - 3);  // truncated footer
  writeBytes(path, bytes);
  expectError("truncated");
  bytes = good;
  bytes[bytes.size() - 20] ^= 1;  // a footer range
  writeBytes(path, bytes);
  expectError("footer");
  // A chunk header claiming far more records than its small zstd payload holds: refused from
  // the frame's recorded content size, before the claimed 1.3 GB are allocated.
  bytes = good;
  uint32_t records = 0, rawBytes = 0;
  std::memcpy(&records, &bytes[128 + 4], 4);
  std::memcpy(&rawBytes, &bytes[128 + 24], 4);
  const uint32_t claimed = 1u << 24, claimedBytes = uint32_t(uint64_t(rawBytes) / records * claimed);
  std::memcpy(&bytes[128 + 4], &claimed, 4);
  std::memcpy(&bytes[128 + 24], &claimedBytes, 4);
  writeBytes(path, bytes);
  const long peakBefore = peakResidentKb();
  expectError("claimed records");
  EXPECT_LT(peakResidentKb() - peakBefore, 200 * 1024) << "allocated for the claimed records";
  // A FIFO is not a sample file: refused at once (opening it blocked until a writer came).
  const std::string fifo = tempPath("fifo.samples");
  std::filesystem::remove(fifo);
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const std::string e = readSampleFile(fifo, info, nullptr);
  EXPECT_NE(e.find("not a regular file"), std::string::npos) << e;
  std::filesystem::remove(fifo);
  std::filesystem::remove(path);
}

TEST(SampleFile, FileOfAKilledWriterKeepsItsWholeChunks) {
  const std::string path = tempPath("killed.samples");
  ASSERT_EQ(writeFile(path, SampleCompression::None, 4, /*close=*/false), "");  // no footer
  std::string bytes = readBytes(path);
  bytes.resize(bytes.size() - 50);  // the last chunk is cut
  writeBytes(path, bytes);
  SampleFileInfo info;
  uint64_t records = 0;
  ASSERT_EQ(readSampleFile(path, info, [&](IndexRange, std::span<const SampleRecord> r) { records += r.size(); }), "");
  EXPECT_FALSE(info.complete);
  EXPECT_EQ(records, 200u);
  EXPECT_EQ(info.ranges, (std::vector<IndexRange>{{100, 300}}));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace tex
