// Adaptive binary range coder with context-modelled bits.
//
// Follows the LZMA range coder (Igor Pavlov, LZMA SDK, "LzmaEnc.c"/"LzmaDec.c",
// public domain; described in the xz file format notes and in G. N. N. Martin,
// "Range encoding: an algorithm for removing redundancy from a digitised
// message", 1979) with three changes, all specified in spec/README.md
// section "Range decoder":
//   * 16-bit probabilities with a count-driven adaptation rate (fast while a
//     context is young, 1/128 once it has seen 63 bits), in the spirit of
//     CABAC/AV1 adaptive models; small streams learn fast.
//   * The always-zero first byte of an LZMA stream is not written, and the
//     flush writes only as many bytes as are needed: the decoder reads up to
//     4 bytes past the end of a stream as zeros.
//   * Uniform symbols over [0, n) are coded by range division.
//
// The decoder never reads outside its span: reads past the end return 0 and
// are counted; more than kMaxOverread of them, or a uniform symbol out of its
// range, put the decoder in a sticky error state (RcError) that the caller
// turns into a status (truncated / bad_value).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace gltfwarp::rc {

constexpr uint32_t kProbOne = 1u << 16;     // probabilities are in 1/65536
constexpr uint32_t kProbMin = 32;           // P(0) is kept in [kProbMin, kProbOne - kProbMin]
constexpr uint32_t kTop = 1u << 24;         // renormalise while range < kTop
constexpr uint32_t kMaxOverread = 4;        // zero bytes a decoder may read past the end
constexpr uint32_t kMaxUniform = 1u << 16;  // largest n of a single uniform symbol
constexpr uint32_t kEgPrefix = 16;          // contexts of an Exp-Golomb length prefix

// One adaptive binary context: P(bit = 0) and how many bits it has seen.
struct BitModel {
  uint16_t p0 = 1u << 15;
  uint8_t count = 0;
  void update(uint32_t bit);
};

enum class RcError : uint8_t { none = 0, overread, bad_symbol };

class Encoder {
 public:
  void bit(BitModel& m, uint32_t b);
  void equiprobable(uint32_t b);                            // p0 = 1/2, no adaptation
  void uniform(uint32_t v, uint32_t n);                     // v < n, n <= kMaxUniform; n == 1 codes nothing
  void uniform32(uint32_t v, uint64_t n);                   // v < n, n <= 2^32
  void tree(BitModel* models, uint32_t nbits, uint32_t v);  // models[1 << nbits], MSB first
  // v >= 0 as an adaptive Exp-Golomb code: prefix[0..kEgPrefix) contexts for the
  // unary length, then the remaining bits equiprobable.
  void exp_golomb(BitModel* prefix, uint32_t v);
  // Ends the stream and returns its bytes (the encoder is spent afterwards).
  std::vector<uint8_t> finish();

 private:
  void shift_low();
  void normalize();
  uint64_t low_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint8_t cache_ = 0;
  uint64_t cache_size_ = 1;
  bool first_ = true;  // the first byte of the stream is always 0 and is not written
  std::vector<uint8_t> out_;
};

class Decoder {
 public:
  explicit Decoder(std::span<const uint8_t> bytes);
  uint32_t bit(BitModel& m);
  uint32_t equiprobable();
  uint32_t uniform(uint32_t n);
  uint32_t uniform32(uint64_t n);
  uint32_t tree(BitModel* models, uint32_t nbits);
  uint32_t exp_golomb(BitModel* prefix);

  RcError error() const { return error_; }
  bool failed() const { return error_ != RcError::none; }
  // True when every byte of the span was consumed (a valid stream uses all of them).
  bool fully_consumed() const { return pos_ >= bytes_.size(); }

 private:
  uint32_t next_byte();
  void normalize();
  uint32_t split(uint32_t p0);  // decode one bit with P(0) = p0 / 2^16
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
  uint32_t range_ = 0xFFFFFFFFu;
  uint32_t code_ = 0;
  RcError error_ = RcError::none;
};

}  // namespace gltfwarp::rc
