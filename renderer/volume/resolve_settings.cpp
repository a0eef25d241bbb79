#include "renderer/volume/resolve_settings.hpp"

namespace prismoid::volume {

const char* interval_pass_name(const ResolveSettings& settings) {
  if (settings.march.enabled) {
    switch (settings.quantity) {
      case Quantity::Color: return "interval-march (color)";
      case Quantity::Isosurface: return "interval-march (isosurface)";
      default: return "interval-march";
    }
  }
  return settings.quantity == Quantity::Color ? "interval-shading (emission)" : "interval-shading";
}

}  // namespace prismoid::volume
