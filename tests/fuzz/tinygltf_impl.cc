// Fuzz builds compile tinygltf from its header (instead of linking Debian's
// shared library) so the sanitizers see inside it. Images are never decoded.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
