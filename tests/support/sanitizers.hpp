// Whether this test program is built with AddressSanitizer + UBSan (the CI's second tree,
// tools/test.sh). The instrumented SPH pair loops and MPM transfers run 40-50x slower than in
// Release (the porous SPH Hugoniot: 3.6 s against 186 s, session 16's CI log), so a few
// validation-size tests run a reduced form there: the same code paths with fewer or smaller runs;
// their full form, with every physics bound, runs in the Release tree of the same CI. Each use
// says what it leaves out and which sanitized test still covers that path.
#pragma once

namespace shatter::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderSanitizers = true;
#else
inline constexpr bool kUnderSanitizers = false;
#endif

}  // namespace shatter::test
