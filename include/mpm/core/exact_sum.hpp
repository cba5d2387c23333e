#pragma once
/// The exact sum of doubles, rounded once when read: a fixed-point number wide enough for every finite double
/// (2^-1074 to 2^1024) held in 32-bit limbs of 64-bit integers, so that no term is rounded when it is added.
/// Integer addition is associative, so the sum is the same bits in any order and any grouping: over threads,
/// over ranks (Communicator::sum adds the limbs), over tiles. A global figure of a distributed run (an
/// energy, a momentum, a reaction) is the same bits whatever the division (docs/scaling.md).
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

namespace mpm {

class ExactSum {
 public:
  /// Limb k weighs 2^(32 k - 1074); 68 limbs reach 2^1102, above the largest double times 2^31 terms.
  static constexpr int limbs = 68;

  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const int exponent = static_cast<int>((bits >> 52) & 0x7ff);
    if (exponent == 0x7ff) {  // infinite or not a number: counted apart, read as IEEE addition would give
      ++special_[(bits & ((std::uint64_t{1} << 52) - 1)) ? 2 : (bits >> 63)];
      return;
    }
    std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
    if (exponent > 0) mantissa |= std::uint64_t{1} << 52;
    if (mantissa == 0) return;
    // x = +-mantissa * 2^(max(exponent, 1) - 1075): its lowest bit sits at position max(exponent, 1) - 1
    // above 2^-1074.
    const int position = (exponent > 0 ? exponent : 1) - 1;
    const int k = position >> 5, shift = position & 31;
    // mantissa * 2^shift, up to 84 bits: the low 64 and the rest.
    const std::uint64_t low = mantissa << shift, high = shift ? mantissa >> (64 - shift) : 0;
    const std::int64_t sign = (bits >> 63) ? -1 : 1;
    limb_[k] += sign * static_cast<std::int64_t>(low & 0xffffffffu);
    limb_[k + 1] += sign * static_cast<std::int64_t>(low >> 32);
    limb_[k + 2] += sign * static_cast<std::int64_t>(high);
    // Each add moves a limb by less than 2^32: 2^30 of them fit in 63 bits; then the carries are settled.
    if (++adds_ == (std::int64_t{1} << 30)) normalize();
  }

  /// Add another exact sum (the other thread's, tile's or rank's).
  void add(const ExactSum& o) {
    normalize();
    ExactSum other = o;
    other.normalize();
    for (int k = 0; k < limbs; ++k) limb_[k] += other.limb_[k];
    for (int s = 0; s < 3; ++s) special_[s] += other.special_[s];
    normalize();
  }

  /// The sum rounded to the nearest double (ties to even, except below the smallest normal double, which may
  /// round twice); +-infinity or NaN when such terms were added, as IEEE addition of them would give.
  double value() const {
    if (special_[2] > 0 || (special_[0] > 0 && special_[1] > 0)) return std::nan("");
    if (special_[0] > 0) return INFINITY;
    if (special_[1] > 0) return -INFINITY;
    ExactSum m = *this;
    m.normalize();
    const bool negative = m.limb_[limbs - 1] < 0;
    if (negative) {
      for (std::int64_t& l : m.limb_) l = -l;
      m.normalize();
    }
    int top = limbs - 1;
    while (top >= 0 && m.limb_[top] == 0) --top;
    if (top < 0) return 0.0;
    if (top >= limbs - 2) return negative ? -INFINITY : INFINITY;  // at least 2^1038
    // The top 64 bits of the top three limbs (each below 2^32 once settled), with every bit below them ORed
    // into the lowest: converting those 64 bits to 53 then rounds as the exact value would.
    const auto limb = [&](int k) {
      return k >= 0 ? static_cast<std::uint64_t>(m.limb_[k]) : std::uint64_t{0};
    };
    const int width = static_cast<int>(std::bit_width(limb(top)));  // 1 .. 32
    std::uint64_t kept =
        (limb(top) << (64 - width)) | (limb(top - 1) << (32 - width)) | (limb(top - 2) >> width);
    bool sticky = (limb(top - 2) & ((std::uint64_t{1} << width) - 1)) != 0;
    for (int k = 0; k < top - 2; ++k) sticky = sticky || m.limb_[k] != 0;
    if (sticky) kept |= 1;
    const double magnitude = std::ldexp(static_cast<double>(kept), 32 * (top - 2) - 1074 + width);
    return negative ? -magnitude : magnitude;
  }

  /// The state as integers (limbs, then the counts of +inf, -inf and NaN terms), settled: adding these arrays
  /// element by element over ranks and reading them back with from_integers is the sum over all.
  std::vector<std::int64_t> integers() const {
    ExactSum m = *this;
    m.normalize();
    std::vector<std::int64_t> out(m.limb_.begin(), m.limb_.end());
    out.insert(out.end(), m.special_.begin(), m.special_.end());
    return out;
  }
  static ExactSum from_integers(const std::vector<std::int64_t>& a) {
    ExactSum s;
    for (int k = 0; k < limbs; ++k) s.limb_[k] = a[static_cast<std::size_t>(k)];
    for (int j = 0; j < 3; ++j) s.special_[j] = a[static_cast<std::size_t>(limbs + j)];
    s.normalize();
    return s;
  }
  static constexpr std::size_t integer_count = limbs + 3;

 private:
  /// Settle the carries: every limb but the top one into [0, 2^32), the top one signed. The representation is
  /// then unique.
  void normalize() {
    for (int k = 0; k + 1 < limbs; ++k) {
      const std::int64_t carry = limb_[k] >> 32;  // floor division by 2^32
      limb_[k] -= carry * (std::int64_t{1} << 32);
      limb_[k + 1] += carry;
    }
    adds_ = 0;
  }

  std::array<std::int64_t, limbs> limb_{};
  std::array<std::int64_t, 3> special_{};  ///< terms +inf, -inf, NaN
  std::int64_t adds_ = 0;
};

}  // namespace mpm
