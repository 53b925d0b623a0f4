// Fuzz builds compile tinygltf from its header (instead of linking Debian's
// shared library) so the sanitizers see inside it. Images are never decoded
// (TINYGLTF_NO_STB_IMAGE… are set for the whole engine in engine/CMakeLists.txt).
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
