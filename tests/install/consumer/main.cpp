// The README's ten-line library example, built against the installed package.
#include <cstdio>

#include <hsr/io.hpp>
#include <hsr/render.hpp>

int main() {
  const hsr::Scene scene = hsr::loadScene("spheres:1000");
  const hsr::Camera camera = hsr::frameScene(scene, 320, 240);
  const hsr::Frame frame = hsr::render(scene, camera);  // colour, depth, ids, overdraw, stats
  hsr::writePng("consumer.png", frame.width, frame.height, 3, hsr::picture(frame, "color").data());
  std::printf("%llu fragments written\n", static_cast<unsigned long long>(frame.stats.fragments_written));
  return frame.stats.fragments_written > 0 ? 0 : 1;
}
