// The one translation unit that compiles tinygltf (Debian's header-only libtinygltf-dev, with
// nlohmann-json). Images are never read or written: STB and external images are disabled by the
// compile definitions of the CMake target shellcontract_tinygltf.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
