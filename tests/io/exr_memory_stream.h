// ExrMemoryStream: an Imf::IStream over bytes in memory, so tests read what io::encode_exr
// produced with OpenEXR's own InputFile.
#pragma once

#include <ImfIO.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace sweepd::io::test_support {

class ExrMemoryStream : public Imf::IStream {
 public:
  explicit ExrMemoryStream(const std::vector<std::uint8_t>& bytes)
      : Imf::IStream("memory"), bytes_(bytes) {}
  bool read(char c[], int n) override {
    if (position_ + n > bytes_.size()) throw std::runtime_error("read past the end");
    std::memcpy(c, bytes_.data() + position_, n);
    position_ += n;
    return position_ < bytes_.size();
  }
  std::uint64_t tellg() override { return position_; }
  void seekg(std::uint64_t position) override { position_ = position; }

 private:
  const std::vector<std::uint8_t>& bytes_;
  std::size_t position_ = 0;
};

}  // namespace sweepd::io::test_support
