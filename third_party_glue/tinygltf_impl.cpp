// The one translation unit that instantiates tinygltf (Debian's header).
// Built with hidden visibility so that our calls bind to this copy and never to
// the copy of tinygltf that libdraco.so exports.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
