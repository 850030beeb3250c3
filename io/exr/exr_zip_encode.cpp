#include "io/exr/exr_zip_encode.h"

#include <IlmThreadPool.h>
#include <half.h>
#include <libdeflate.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace sweepd::io {
namespace {

constexpr int kLinesPerBlock = 16;  // ZIP's block (ZIPS has 1)

// One channel of the file: where its values start, how far apart (floats), and as what.
struct Channel {
  std::string name;
  const float* values = nullptr;
  int stride = 1;
  bool half = false;
};

// Little-endian appends, as every EXR number is stored.
template <typename T>
void put(std::vector<std::uint8_t>& out, T value) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

void put_attribute(std::vector<std::uint8_t>& out, std::string_view name, std::string_view type,
                   const std::vector<std::uint8_t>& value) {
  out.insert(out.end(), name.begin(), name.end());
  out.push_back(0);
  out.insert(out.end(), type.begin(), type.end());
  out.push_back(0);
  put(out, static_cast<std::int32_t>(value.size()));
  out.insert(out.end(), value.begin(), value.end());
}

template <typename... T>
std::vector<std::uint8_t> value_of(T... numbers) {
  std::vector<std::uint8_t> value;
  (put(value, numbers), ...);
  return value;
}

std::vector<std::uint8_t> text(std::string_view s) { return {s.begin(), s.end()}; }

std::string hex16(std::uint64_t value) {
  char digits[17];
  std::snprintf(digits, sizeof digits, "%016llx", static_cast<unsigned long long>(value));
  return digits;
}

void put_header(std::vector<std::uint8_t>& out, const ExrLayers& layers, const ExrOptions& options,
                const std::vector<Channel>& channels) {
  put(out, std::uint32_t{20000630});  // the magic number
  put(out, std::uint32_t{2});         // version 2, single-part scan lines, short names
  std::vector<std::uint8_t> list;
  for (const Channel& channel : channels) {
    list.insert(list.end(), channel.name.begin(), channel.name.end());
    list.push_back(0);
    put(list, std::int32_t{channel.half ? 1 : 2});  // HALF, FLOAT
    put(list, std::uint32_t{0});                    // pLinear 0 and three reserved bytes
    put(list, std::int32_t{1});                     // x sampling
    put(list, std::int32_t{1});                     // y sampling
  }
  list.push_back(0);
  const auto window = value_of(0, 0, layers.width - 1, layers.height - 1);
  // Sorted by name, as OpenEXR writes them.
  put_attribute(out, "channels", "chlist", list);
  put_attribute(out, "compression", "compression", {3});  // ZIP_COMPRESSION
  put_attribute(out, "dataWindow", "box2i", window);
  put_attribute(out, "displayWindow", "box2i", window);
  put_attribute(out, "frame", "int", value_of(static_cast<std::int32_t>(options.frame)));
  put_attribute(out, "lineOrder", "lineOrder", {0});  // INCREASING_Y
  put_attribute(out, "model", "string", text(options.model));
  put_attribute(out, "pixelAspectRatio", "float", value_of(1.0f));
  put_attribute(out, "poseHash", "string", text(hex16(options.pose_hash)));
  put_attribute(out, "screenWindowCenter", "v2f", value_of(0.0f, 0.0f));
  put_attribute(out, "screenWindowWidth", "float", value_of(1.0f));
  put_attribute(out, "space", "string", text(options.space));
  put_attribute(out, "units", "string", text(options.units));
  out.push_back(0);  // end of the header
}

struct CompressorDeleter {
  void operator()(libdeflate_compressor* compressor) const { libdeflate_free_compressor(compressor); }
};

// One block's chunk (y, size, data) into `chunk`: lines packed channel after channel, split
// into even and odd bytes, predicted, deflated (or stored when that is not smaller).
void encode_block(const std::vector<Channel>& channels, int width, int first_line, int lines,
                  int level, std::vector<std::uint8_t>& chunk) {
  thread_local std::vector<std::uint8_t> packed, prepared;
  thread_local std::unique_ptr<libdeflate_compressor, CompressorDeleter> compressor;
  thread_local int compressor_level = 0;
  if (!compressor || compressor_level != level) {
    compressor.reset(libdeflate_alloc_compressor(level));
    compressor_level = level;
    if (!compressor) throw std::runtime_error("EXR position map: libdeflate has no memory");
  }
  std::size_t line_bytes = 0;
  for (const Channel& channel : channels) line_bytes += (channel.half ? 2u : 4u) * width;
  packed.resize(line_bytes * static_cast<std::size_t>(lines));
  std::uint8_t* out = packed.data();
  for (int y = first_line; y < first_line + lines; ++y) {
    for (const Channel& channel : channels) {
      const float* row = channel.values + static_cast<std::size_t>(y) * width * channel.stride;
      const auto stride = static_cast<std::size_t>(channel.stride);
      if (channel.half) {
        for (int x = 0; x < width; ++x, out += 2) {
          const std::uint16_t bits = Imath::half(row[x * stride]).bits();
          std::memcpy(out, &bits, 2);
        }
      } else {
        for (int x = 0; x < width; ++x, out += 4) std::memcpy(out, &row[x * stride], 4);
      }
    }
  }
  // OpenEXR's ZIP: the even bytes, then the odd ones; each byte then minus the one before.
  const std::size_t size = packed.size();
  prepared.resize(size);
  std::uint8_t* even = prepared.data();
  std::uint8_t* odd = prepared.data() + (size + 1) / 2;
  for (std::size_t i = 0; i < size; i += 2) {
    *even++ = packed[i];
    if (i + 1 < size) *odd++ = packed[i + 1];
  }
  for (std::size_t i = size; i-- > 1;)  // backwards: prepared[i - 1] is still a byte, not a difference
    prepared[i] = static_cast<std::uint8_t>(prepared[i] - prepared[i - 1] + 128);
  chunk.resize(8 + libdeflate_zlib_compress_bound(compressor.get(), size));
  std::size_t compressed = libdeflate_zlib_compress(compressor.get(), prepared.data(), size,
                                                    chunk.data() + 8, chunk.size() - 8);
  if (compressed == 0 || compressed >= size) {  // stored as packed: the reader sees the size
    std::memcpy(chunk.data() + 8, packed.data(), size);
    compressed = size;
  }
  chunk.resize(8 + compressed);
  const std::int32_t header[2] = {first_line, static_cast<std::int32_t>(compressed)};
  std::memcpy(chunk.data(), header, sizeof header);
}

// Blocks [first, last) of the file, each into its own chunk.
class BlockTask : public IlmThread::Task {
 public:
  BlockTask(IlmThread::TaskGroup* group, const std::vector<Channel>& channels, int width,
            int height, int level, int first, int last, std::vector<std::vector<std::uint8_t>>& chunks,
            std::string& failure, std::atomic<int>& finished)
      : IlmThread::Task(group), channels_(channels), width_(width), height_(height),
        level_(level), first_(first), last_(last), chunks_(chunks), failure_(failure),
        finished_(finished) {}
  void execute() override {
    try {
      for (int block = first_; block < last_; ++block) {
        const int first_line = block * kLinesPerBlock;
        encode_block(channels_, width_, first_line,
                     std::min(kLinesPerBlock, height_ - first_line), level_,
                     chunks_[static_cast<std::size_t>(block)]);
      }
    } catch (const std::exception& error) {
      failure_ = error.what();  // one task at most writes it: the others' blocks differ
    }
    finished_.fetch_add(1, std::memory_order_release);
  }

 private:
  const std::vector<Channel>& channels_;
  int width_, height_, level_, first_, last_;
  std::vector<std::vector<std::uint8_t>>& chunks_;
  std::string& failure_;
  std::atomic<int>& finished_;
};

}  // namespace

void encode_zip_exr(const ExrLayers& layers, const ExrOptions& options,
                    std::vector<std::uint8_t>& bytes) {
  std::vector<Channel> channels;
  if (!layers.coverage.empty()) channels.push_back({"A", layers.coverage.data(), 1, false});
  static const char* const kAxes[3] = {".X", ".Y", ".Z"};
  for (int c = 0; c < 3 && !layers.normals.empty(); ++c)
    channels.push_back({std::string("N") + kAxes[c], layers.normals.data() + c, 3,
                        options.half_normals});
  for (int c = 0; c < 3; ++c)
    channels.push_back({std::string("P") + kAxes[c], layers.positions.data() + c, 3, false});

  const int blocks = (layers.height + kLinesPerBlock - 1) / kLinesPerBlock;
  thread_local std::vector<std::vector<std::uint8_t>> chunks;
  chunks.resize(static_cast<std::size_t>(blocks));
  // As many tasks as the pool has threads (none: all here, at once), each a run of blocks.
  const int tasks =
      std::clamp(IlmThread::ThreadPool::globalThreadPool().numThreads(), 1, blocks);
  std::vector<std::string> failures(static_cast<std::size_t>(tasks));
  // The TaskGroup waits for its tasks through atomics inside libIlmThread, which is not built
  // with ThreadSanitizer: it cannot see that this wait orders the tasks' writes before the
  // reads below, and reported a race (make tsan, render_frames_test). Each task also publishes
  // its end here, in code TSan sees; the count checks that every task ran.
  std::atomic<int> finished{0};
  {
    IlmThread::TaskGroup group;  // waits for its tasks when it goes
    for (int t = 0; t < tasks; ++t) {
      IlmThread::ThreadPool::addGlobalTask(new BlockTask(
          &group, channels, layers.width, layers.height, options.zip_level, blocks * t / tasks,
          blocks * (t + 1) / tasks, chunks, failures[static_cast<std::size_t>(t)], finished));
    }
  }
  if (finished.load(std::memory_order_acquire) != tasks)
    throw std::logic_error("ZIP EXR encoding: a block task did not run");
  for (const std::string& failure : failures)
    if (!failure.empty()) throw std::runtime_error(failure);

  bytes.clear();
  put_header(bytes, layers, options, channels);
  std::uint64_t offset = bytes.size() + sizeof(std::uint64_t) * static_cast<std::size_t>(blocks);
  for (const std::vector<std::uint8_t>& chunk : chunks) {
    put(bytes, offset);
    offset += chunk.size();
  }
  for (const std::vector<std::uint8_t>& chunk : chunks)
    bytes.insert(bytes.end(), chunk.begin(), chunk.end());
}

}  // namespace sweepd::io
