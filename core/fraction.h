// Exact positions on the lines where tiles meet. A tile at level L with r cells puts its points at
// (i·r + k) / (r·2^L) of its root; two tiles must agree on a shared point bit for bit whatever
// their rates, and a point must be recognised from either side of a base edge (t and 1 − t), so
// positions are kept exactly and turned into doubles only to evaluate. Every such value is
// num / (odd · 2^exp) with a small odd part (a product of rates), kept canonical so that equal
// values are equal fields; sums and products are taken in 128 bits.
#pragma once

#include <cmath>
#include <cstdint>

namespace tessera {

struct Fraction {
  int64_t num = 0;  // value = num / (odd · 2^exp)
  int64_t odd = 1;  // odd, > 0, coprime with num
  int32_t exp = 0;  // >= 0; num is odd unless exp == 0

  static Fraction canonical(__int128 n, __int128 odd, int exp) {
    if (n == 0) return {0, 1, 0};
    const bool small = n > -(__int128(1) << 62) && n < (__int128(1) << 62);
    if (odd > 1) {
      // Odd parts are products of a few rates: 64 bits hold them.
      const uint64_t o = uint64_t(odd);
      uint64_t a = small ? uint64_t(n < 0 ? -int64_t(n) : int64_t(n)) % o : uint64_t((n < 0 ? -n : n) % odd);
      uint64_t b = o;
      while (a != 0) {
        const uint64_t r = b % a;
        b = a, a = r;
      }
      if (b > 1) {
        n = small ? __int128(int64_t(n) / int64_t(b)) : n / __int128(b);
        odd /= __int128(b);
      }
    }
    if (exp > 0) {
      const uint64_t low = uint64_t(n);
      const int zeros = low != 0 ? __builtin_ctzll(low) : 64 + __builtin_ctzll(uint64_t(n >> 64));
      const int k = zeros < exp ? zeros : exp;
      n >>= k, exp -= k;
    }
    return {int64_t(n), int64_t(odd), exp};
  }
  // num / den for any den != 0.
  static Fraction make(__int128 num, __int128 den) {
    if (den < 0) num = -num, den = -den;
    const uint64_t low = uint64_t(den);
    const int exp = low != 0 ? __builtin_ctzll(low) : 64 + __builtin_ctzll(uint64_t(den >> 64));
    return canonical(num, den >> exp, exp);
  }
  static Fraction integer(int64_t n) { return {n, 1, 0}; }

  double value() const { return double(std::ldexp((long double)num / (long double)odd, -exp)); }

  // num·odd_other·2^(e − exp): this value scaled to the common denominator odd·odd_other·2^e.
  __int128 scaledTo(int64_t otherOdd, int e) const { return __int128(num) * otherOdd << (e - exp); }

  friend Fraction operator+(const Fraction& a, const Fraction& b) {
    const int e = a.exp > b.exp ? a.exp : b.exp;
    return canonical(a.scaledTo(b.odd, e) + b.scaledTo(a.odd, e), __int128(a.odd) * b.odd, e);
  }
  friend Fraction operator-(const Fraction& a, const Fraction& b) { return a + Fraction{-b.num, b.odd, b.exp}; }
  friend Fraction operator/(const Fraction& a, const Fraction& b) {
    // (a.num / (a.odd 2^a.exp)) · (b.odd 2^b.exp / b.num)
    const int shift = b.exp - a.exp;
    const __int128 num = __int128(a.num) * b.odd, den = __int128(a.odd) * b.num;
    return shift >= 0 ? make(num << shift, den) : make(num, den << -shift);
  }
  Fraction times(int64_t k) const { return make(__int128(num) * k, __int128(odd) << exp); }
  // This value times 2^-k.
  Fraction halved(int k) const { return canonical(num, odd, exp + k); }
  Fraction over(int64_t k) const { return make(num, (__int128(odd) << exp) * k); }

  friend bool operator==(const Fraction& a, const Fraction& b) {
    return a.num == b.num && a.odd == b.odd && a.exp == b.exp;
  }
  friend bool operator<(const Fraction& a, const Fraction& b) {
    const int e = a.exp > b.exp ? a.exp : b.exp;
    return a.scaledTo(b.odd, e) < b.scaledTo(a.odd, e);
  }
  friend bool operator<=(const Fraction& a, const Fraction& b) { return !(b < a); }
};

}  // namespace tessera
