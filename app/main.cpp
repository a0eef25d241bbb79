#include <string>
#include <vector>

#include "app/cli.hpp"
#include "io/isolated_read.hpp"

int main(int argc, char** argv) {
  prismoid::io::serve_isolated_child(argc, argv);  // a reader child started by this program does its work and exits here
  std::vector<std::string> args(argv + 1, argv + argc);
  return prismoid::app::run_cli(args);
}
