#pragma once
// Whether this build runs under AddressSanitizer, which reserves terabytes of address space for
// its shadow memory as a process starts and holds a few hundred MiB of its own: an OS data limit
// (RLIMIT_DATA) refuses the first, so the GLSL worker runs without one there, and the second
// swamps a peak memory measured from outside, so the tests check only the outcome there.

namespace heightmarch {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace heightmarch
