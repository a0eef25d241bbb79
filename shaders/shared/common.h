// Included by C++ and GLSL alike: the vocabulary for structures that both sides read.
// Members are only vec4, uvec4, mat4 (16-byte aligned), so std140/std430 and C++ agree;
// every struct gets static_asserts on the C++ side.
#ifndef PRISMOID_SHARED_COMMON_H
#define PRISMOID_SHARED_COMMON_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
#define PRISMOID_SHARED_BEGIN namespace prismoid::gpu {
#define PRISMOID_SHARED_END }
PRISMOID_SHARED_BEGIN
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using mat4 = glm::mat4;
using uint = std::uint32_t;
PRISMOID_SHARED_END
#else
#define PRISMOID_SHARED_BEGIN
#define PRISMOID_SHARED_END
#endif

#endif
