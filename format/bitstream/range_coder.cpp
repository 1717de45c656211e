// Adaptive binary range coder: see range_coder.h for the source it follows and
// spec/README.md ("Range decoder") for the normative arithmetic.
#include "format/bitstream/range_coder.h"

#include <algorithm>
#include <bit>
#include <cassert>

namespace gltfwarp::rc {

void BitModel::update(uint32_t b) {
  // Rate 1/2^shift with shift = bit_width(count + 1): 1, 2, 2, 3 x4, 4 x8, ..., 7.
  const uint32_t shift = static_cast<uint32_t>(std::bit_width(static_cast<uint32_t>(count) + 1u));
  uint32_t p = p0;
  if (b == 0)
    p += (kProbOne - p) >> shift;
  else
    p -= p >> shift;
  p = std::clamp(p, kProbMin, kProbOne - kProbMin);
  p0 = static_cast<uint16_t>(p);
  if (count < 63) ++count;
}

// ---- encoder ---------------------------------------------------------------

void Encoder::shift_low() {
  if (static_cast<uint32_t>(low_) < 0xFF000000u || (low_ >> 32) != 0) {
    const uint8_t carry = static_cast<uint8_t>(low_ >> 32);
    uint8_t temp = cache_;
    do {
      const uint8_t byte = static_cast<uint8_t>(temp + carry);
      if (first_) {
        assert(byte == 0);
        first_ = false;
      } else {
        out_.push_back(byte);
      }
      temp = 0xFF;
    } while (--cache_size_ != 0);
    cache_ = static_cast<uint8_t>(static_cast<uint32_t>(low_) >> 24);
  }
  ++cache_size_;
  low_ = static_cast<uint64_t>(static_cast<uint32_t>(low_) << 8);
}

void Encoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    shift_low();
  }
}

void Encoder::bit(BitModel& m, uint32_t b) {
  const uint32_t bound = (range_ >> 16) * m.p0;
  if (b == 0) {
    range_ = bound;
  } else {
    low_ += bound;
    range_ -= bound;
  }
  m.update(b);
  normalize();
}

void Encoder::equiprobable(uint32_t b) {
  const uint32_t bound = (range_ >> 16) * (1u << 15);
  if (b == 0) {
    range_ = bound;
  } else {
    low_ += bound;
    range_ -= bound;
  }
  normalize();
}

void Encoder::uniform(uint32_t v, uint32_t n) {
  assert(n >= 1 && n <= kMaxUniform && v < n);
  if (n == 1) return;
  const uint32_t r = range_ / n;
  low_ += static_cast<uint64_t>(r) * v;
  range_ = r;
  normalize();
}

void Encoder::uniform32(uint32_t v, uint64_t n) {
  assert(n >= 1 && n <= (uint64_t{1} << 32) && v < n);
  if (n <= kMaxUniform) return uniform(v, static_cast<uint32_t>(n));
  const uint32_t hi_n = static_cast<uint32_t>(((n - 1) >> 16) + 1);
  const uint32_t hi = v >> 16;
  uniform(hi, hi_n);
  const uint32_t lo_n = (hi == hi_n - 1) ? static_cast<uint32_t>(((n - 1) & 0xFFFFu) + 1) : kMaxUniform;
  uniform(v & 0xFFFFu, lo_n);
}

void Encoder::tree(BitModel* models, uint32_t nbits, uint32_t v) {
  uint32_t m = 1;
  for (uint32_t i = nbits; i-- > 0;) {
    const uint32_t b = (v >> i) & 1u;
    bit(models[m], b);
    m = 2 * m + b;
  }
}

void Encoder::exp_golomb(BitModel* prefix, uint32_t v) {
  const uint64_t w = uint64_t{v} + 1;
  const uint32_t k = static_cast<uint32_t>(std::bit_width(w)) - 1;  // 0..32
  for (uint32_t i = 0; i < k; ++i) bit(prefix[std::min(i, kEgPrefix - 1)], 1);
  if (k < 32) bit(prefix[std::min(k, kEgPrefix - 1)], 0);
  for (uint32_t i = k; i-- > 0;) equiprobable(static_cast<uint32_t>(w >> i) & 1u);
}

std::vector<uint8_t> Encoder::finish() {
  // Pick the value in [low, low + range) with the most trailing zero bytes;
  // the decoder supplies those zeros itself (kMaxOverread).
  const uint64_t hi = low_ + range_;  // exclusive
  for (uint32_t keep = 0; keep <= 4; ++keep) {
    const uint64_t mask = keep == 4 ? 0 : (uint64_t{0xFFFFFFFFu} >> (8 * keep));
    const uint64_t v = (low_ + mask) & ~mask;
    if (v < hi) {
      low_ = v;
      break;
    }
  }
  for (int i = 0; i < 5; ++i) shift_low();
  for (uint32_t i = 0; i < kMaxOverread && !out_.empty() && out_.back() == 0; ++i) out_.pop_back();
  return std::move(out_);
}

// ---- decoder ---------------------------------------------------------------

Decoder::Decoder(std::span<const uint8_t> bytes) : bytes_(bytes) {
  for (int i = 0; i < 4; ++i) code_ = (code_ << 8) | next_byte();
}

uint32_t Decoder::next_byte() {
  const size_t p = pos_++;
  if (p < bytes_.size()) return bytes_[p];
  if (p - bytes_.size() >= kMaxOverread && error_ == RcError::none) error_ = RcError::overread;
  return 0;
}

void Decoder::normalize() {
  while (range_ < kTop) {
    range_ <<= 8;
    code_ = (code_ << 8) | next_byte();
  }
}

// One binary decision with P(0) = p0 / 2^16, then renormalisation.
uint32_t Decoder::split(uint32_t p0) {
  const uint32_t bound = (range_ >> 16) * p0;
  uint32_t b;
  if (code_ < bound) {
    range_ = bound;
    b = 0;
  } else {
    code_ -= bound;
    range_ -= bound;
    b = 1;
  }
  normalize();
  return b;
}

uint32_t Decoder::bit(BitModel& m) {
  const uint32_t b = split(m.p0);
  m.update(b);
  return b;
}

uint32_t Decoder::equiprobable() { return split(1u << 15); }

uint32_t Decoder::uniform(uint32_t n) {
  if (n <= 1) return 0;
  const uint32_t r = range_ / n;
  uint32_t q = code_ / r;
  if (q >= n) {  // only a corrupt stream lands in the unused tail of the range
    if (error_ == RcError::none) error_ = RcError::bad_symbol;
    q = n - 1;
  }
  code_ -= q * r;
  range_ = r;
  normalize();
  return q;
}

uint32_t Decoder::uniform32(uint64_t n) {
  if (n <= kMaxUniform) return uniform(static_cast<uint32_t>(n));
  const uint32_t hi_n = static_cast<uint32_t>(((n - 1) >> 16) + 1);
  const uint32_t hi = uniform(hi_n);
  const uint32_t lo_n = (hi == hi_n - 1) ? static_cast<uint32_t>(((n - 1) & 0xFFFFu) + 1) : kMaxUniform;
  return (hi << 16) | uniform(lo_n);
}

uint32_t Decoder::tree(BitModel* models, uint32_t nbits) {
  uint32_t m = 1;
  for (uint32_t i = 0; i < nbits; ++i) m = 2 * m + bit(models[m]);
  return m - (1u << nbits);
}

uint32_t Decoder::exp_golomb(BitModel* prefix) {
  uint32_t k = 0;
  while (k < 32 && bit(prefix[std::min(k, kEgPrefix - 1)]) == 1) {
    ++k;
    if (failed()) return 0;
  }
  uint64_t w = 1;
  for (uint32_t i = 0; i < k; ++i) w = (w << 1) | equiprobable();
  if (w - 1 > 0xFFFFFFFFu) {  // only k == 32 with a non-zero suffix
    if (error_ == RcError::none) error_ = RcError::bad_symbol;
    return 0;
  }
  return static_cast<uint32_t>(w - 1);
}

}  // namespace gltfwarp::rc
