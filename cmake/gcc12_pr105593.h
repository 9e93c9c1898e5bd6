// Force-included into every translation unit of our own targets when GCC < 13 compiles for a CPU with
// AVX-512 (-march=native): GCC bug 105593. The intrinsics in <avx512fintrin.h> initialise a register
// from itself (`__m512d __Y = __Y;`), and GCC 12 reports each inlined use as "used uninitialized" or
// "may be used uninitialized" (-Wuninitialized, -Wmaybe-uninitialized) — dozens per file that uses
// Eigen's AVX-512 packets. GCC 13 fixed it with pragmas in the header itself; this does the same from
// outside: the warnings are silenced for the intrinsic headers only, which their include guards then
// keep from being read again, and stay on for our code.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ < 13 && defined(__AVX512F__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#endif
