#include "app/viewer/camera_line.hpp"

#include <cstdio>
#include <sstream>
#include <vector>

#include "app/common/cli_args.hpp"

namespace prismoid::app {

namespace {

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string vec(const glm::dvec3& v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }

}  // namespace

std::string camera_line(const Camera& c) {
  return "--eye " + vec(c.eye) + " --target " + vec(c.target) + " --up " + vec(c.up) + " --fovy " + number(c.fovy_degrees) +
         " --near " + number(c.near_distance);
}

Camera camera_from_line(const std::string& line, const Bounds& bounds) {
  std::istringstream words(line);
  std::vector<std::string> args;
  for (std::string w; words >> w;) args.push_back(w);
  return camera_from(parse(args, 0, kCameraOptions, {}), bounds);
}

}  // namespace prismoid::app
