// Stable 64-bit FNV-1a hash used for scene content hashes (cache keys).
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>

namespace vs {

class ContentHasher {
 public:
  void addBytes(const void* data, size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < size; ++i) {
      state_ ^= bytes[i];
      state_ *= 0x100000001b3ull;  // FNV-1a 64-bit prime
    }
  }
  // Adds the size (8 bytes, little endian) before the bytes so that concatenations stay distinct.
  void addBlock(const void* data, size_t size) {
    unsigned char length[8];
    for (int i = 0; i < 8; ++i) length[i] = static_cast<unsigned char>(uint64_t(size) >> (8 * i));
    addBytes(length, sizeof length);
    addBytes(data, size);
  }
  void addBlock(const std::string& text) { addBlock(text.data(), text.size()); }
  uint64_t value() const { return state_; }
  std::string hex() const {
    char buffer[17];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(state_));
    return buffer;
  }

 private:
  uint64_t state_ = 0xcbf29ce484222325ull;  // FNV-1a 64-bit offset basis
};

}  // namespace vs
