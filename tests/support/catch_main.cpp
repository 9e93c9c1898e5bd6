// The main of every test executable: Catch2's session, with its exit code (the number of failed
// assertions, capped at 255) mapped to 1, so that no failure count can collide with the skip code of
// support/shared_data.hpp.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>

int main(int argc, char** argv) {
  const int failed = Catch::Session().run(argc, argv);
  return failed == 0 ? 0 : 1;
}
