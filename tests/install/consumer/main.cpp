// The README's ten-line library example, built against the installed package through the
// umbrella header (which also proves every public header compiles outside the source tree).
#include <cstdio>
#include <string>

#include <hsr/hsr.hpp>

int main() {
  const hsr::Scene scene = hsr::loadScene("spheres:1000");
  const hsr::Camera camera = hsr::frameScene(scene, 320, 240);
  const hsr::Frame frame = hsr::render(scene, camera);  // colour, depth, ids, overdraw, stats
  hsr::writePng("consumer.png", frame.width, frame.height, 3, hsr::picture(frame, "color").data());
  std::printf("hsr %s: %llu fragments written\n", std::string(hsr::version()).c_str(),
              static_cast<unsigned long long>(frame.stats.fragments_written));
  return frame.stats.fragments_written > 0 ? 0 : 1;
}
