// The one translation unit that instantiates tinygltf (Debian's header).
// Built with hidden visibility so that our calls bind to this copy and never to
// the copy of tinygltf that libdraco.so exports.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_USE_CPP14
#include <tiny_gltf.h>
