#pragma once
// Whether the GLSL worker runs under its OS data limit (RLIMIT_DATA). An AddressSanitizer build
// reserves terabytes of address space for its shadow memory as it starts, which the limit
// refuses (the worker would abort before its first message), so that build runs the worker
// without it and keeps the memory budget's own checks.

namespace heightmarch {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kWorkerDataLimit = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kWorkerDataLimit = false;
#else
inline constexpr bool kWorkerDataLimit = true;
#endif
#else
inline constexpr bool kWorkerDataLimit = true;
#endif

}  // namespace heightmarch
