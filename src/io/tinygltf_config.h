// tinygltf as conceptmesh builds it: images are encoded and decoded with OpenImageIO
// (io/image_io.h), not stb, and no image is read from outside the file. The one translation
// unit that holds tinygltf's code defines TINYGLTF_IMPLEMENTATION before including this.
#pragma once
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>
