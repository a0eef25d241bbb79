// The main() of every test executable: GoogleTest's, after io::serve_isolated_child, so that the
// readers a test starts (io/isolated_read.hpp) run in fresh copies of the test executable.
#include <gtest/gtest.h>

#include "io/isolated_read.hpp"

int main(int argc, char** argv) {
  prismoid::io::serve_isolated_child(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
