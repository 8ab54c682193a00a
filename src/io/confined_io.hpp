#pragma once
// The files an import may open. assimp opens the model and whatever it references (an OBJ's
// mtllib, a glTF's buffers and images, a COLLADA's textures) through an Assimp::IOSystem; this
// one opens only regular files that resolve, after symbolic links, inside the model's own
// directory tree (unless references outside are allowed), never a FIFO, device or directory,
// and reports every file it opens so that the import's memory budget can count it.
//
// A refused reference is not an error inside assimp (which might skip it and go on): the first
// refusal is kept, and the import is refused with it as its one line.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include <assimp/DefaultIOSystem.h>

namespace hsr::detail {

class ConfinedIOSystem : public Assimp::DefaultIOSystem {
 public:
  // `model`: the model file as the user named it. `on_open(bytes)` is called for every file
  // opened other than the model itself.
  ConfinedIOSystem(const std::filesystem::path& model, bool allow_outside,
                   std::function<void(std::uint64_t)> on_open);

  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;
  // By stat, never by opening (assimp's own opens the file, and a FIFO blocks that open).
  bool Exists(const char* file) const override;

  // The first refusal's line ("model.obj: references ../x.mtl, outside the model's folder..."),
  // empty if none.
  const std::string& refusal() const { return refusal_; }

 private:
  Assimp::IOStream* refuse(std::string why);

  std::string model_name_;
  std::filesystem::path model_, root_;
  bool allow_outside_;
  std::function<void(std::uint64_t)> on_open_;
  std::string refusal_;
};

}  // namespace hsr::detail
