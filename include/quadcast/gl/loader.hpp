// quadcast/gl/loader.hpp -- one table of the OpenGL 4.5 core entry points quadcast uses, filled from a resolver
#pragma once
// Host-only. The table is filled through the context's own getProcAddress (OSMesa, EGL, GLX,
// a windowing library ...), so the same code runs on every context type and no system loader
// (libepoxy, glbinding, GLAD) is needed. Add a function by adding one X(...) line below.

// GL types and enums: <GL/glcorearb.h>, unless the user already included <GL/gl.h> (which
// brings <GL/glext.h>). The entry-point signatures below are spelled out, so they do not depend
// on which of the two header sets provides the PFNGL...PROC typedefs; tests/gl checks each one
// against glcorearb's typedef.
#if !defined(__gl_h_) && !defined(__gl_glcorearb_h_) && !defined(__gl_glext_h_)
#include <GL/glcorearb.h>
#elif defined(__gl_h_) && !defined(__gl_glext_h_) && !defined(__gl_glcorearb_h_)
#include <GL/glext.h>
#endif
#ifndef APIENTRY
#define APIENTRY
#endif

#include <cstdio>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

// X(return type, name without the "gl" prefix, (parameter list)). Groups are only for reading;
// everything except QUADCAST_GL_FUNCTIONS_GL45 is core in OpenGL 4.3 (asked for first, before the
// context's version is known); quadcast needs 4.5.
#define QUADCAST_GL_FUNCTIONS_STATE(X) \
    X(GLenum, GetError, ()) \
    X(const GLubyte *, GetString, (GLenum name)) \
    X(const GLubyte *, GetStringi, (GLenum name, GLuint index)) \
    X(void, GetIntegerv, (GLenum pname, GLint *data)) \
    X(void, GetIntegeri_v, (GLenum target, GLuint index, GLint *data)) \
    X(void, GetInteger64v, (GLenum pname, GLint64 *data)) \
    X(void, GetFloatv, (GLenum pname, GLfloat *data)) \
    X(void, GetBooleanv, (GLenum pname, GLboolean *data)) \
    X(void, Enable, (GLenum cap)) \
    X(void, Disable, (GLenum cap)) \
    X(GLboolean, IsEnabled, (GLenum cap)) \
    X(void, Enablei, (GLenum target, GLuint index)) \
    X(void, Disablei, (GLenum target, GLuint index)) \
    X(void, Viewport, (GLint x, GLint y, GLsizei width, GLsizei height)) \
    X(void, Scissor, (GLint x, GLint y, GLsizei width, GLsizei height)) \
    X(void, DepthFunc, (GLenum func)) \
    X(void, DepthMask, (GLboolean flag)) \
    X(void, DepthRangef, (GLfloat n, GLfloat f)) \
    X(void, ClearColor, (GLfloat red, GLfloat green, GLfloat blue, GLfloat alpha)) \
    X(void, ClearDepth, (GLdouble depth)) \
    X(void, ClearDepthf, (GLfloat d)) \
    X(void, ClearStencil, (GLint s)) \
    X(void, Clear, (GLbitfield mask)) \
    X(void, ColorMask, (GLboolean red, GLboolean green, GLboolean blue, GLboolean alpha)) \
    X(void, BlendFunc, (GLenum sfactor, GLenum dfactor)) \
    X(void, BlendFuncSeparate, (GLenum sfactorRGB, GLenum dfactorRGB, GLenum sfactorAlpha, GLenum dfactorAlpha)) \
    X(void, BlendEquation, (GLenum mode)) \
    X(void, BlendEquationSeparate, (GLenum modeRGB, GLenum modeAlpha)) \
    X(void, CullFace, (GLenum mode)) \
    X(void, FrontFace, (GLenum mode)) \
    X(void, PolygonMode, (GLenum face, GLenum mode)) \
    X(void, PolygonOffset, (GLfloat factor, GLfloat units)) \
    X(void, StencilFunc, (GLenum func, GLint ref, GLuint mask)) \
    X(void, StencilOp, (GLenum fail, GLenum zfail, GLenum zpass)) \
    X(void, StencilMask, (GLuint mask)) \
    X(void, PixelStorei, (GLenum pname, GLint param)) \
    X(void, LineWidth, (GLfloat width)) \
    X(void, PointSize, (GLfloat size)) \
    X(void, Hint, (GLenum target, GLenum mode)) \
    X(void, Finish, ()) \
    X(void, Flush, ())

#define QUADCAST_GL_FUNCTIONS_SHADERS(X) \
    X(GLuint, CreateShader, (GLenum type)) \
    X(void, ShaderSource, (GLuint shader, GLsizei count, const GLchar *const*string, const GLint *length)) \
    X(void, CompileShader, (GLuint shader)) \
    X(void, GetShaderiv, (GLuint shader, GLenum pname, GLint *params)) \
    X(void, GetShaderInfoLog, (GLuint shader, GLsizei bufSize, GLsizei *length, GLchar *infoLog)) \
    X(void, GetShaderSource, (GLuint shader, GLsizei bufSize, GLsizei *length, GLchar *source)) \
    X(void, DeleteShader, (GLuint shader)) \
    X(GLboolean, IsShader, (GLuint shader)) \
    X(GLuint, CreateProgram, ()) \
    X(void, AttachShader, (GLuint program, GLuint shader)) \
    X(void, DetachShader, (GLuint program, GLuint shader)) \
    X(void, LinkProgram, (GLuint program)) \
    X(void, ValidateProgram, (GLuint program)) \
    X(void, GetProgramiv, (GLuint program, GLenum pname, GLint *params)) \
    X(void, GetProgramInfoLog, (GLuint program, GLsizei bufSize, GLsizei *length, GLchar *infoLog)) \
    X(void, UseProgram, (GLuint program)) \
    X(void, DeleteProgram, (GLuint program)) \
    X(GLboolean, IsProgram, (GLuint program)) \
    X(GLint, GetUniformLocation, (GLuint program, const GLchar *name)) \
    X(GLint, GetAttribLocation, (GLuint program, const GLchar *name)) \
    X(void, BindAttribLocation, (GLuint program, GLuint index, const GLchar *name)) \
    X(void, BindFragDataLocation, (GLuint program, GLuint color, const GLchar *name)) \
    X(GLint, GetFragDataLocation, (GLuint program, const GLchar *name)) \
    X(void, GetActiveUniform, (GLuint program, GLuint index, GLsizei bufSize, GLsizei *length, GLint *size, GLenum *type, GLchar *name)) \
    X(GLuint, GetUniformBlockIndex, (GLuint program, const GLchar *uniformBlockName)) \
    X(void, UniformBlockBinding, (GLuint program, GLuint uniformBlockIndex, GLuint uniformBlockBinding)) \
    X(void, ShaderStorageBlockBinding, (GLuint program, GLuint storageBlockIndex, GLuint storageBlockBinding)) \
    X(GLuint, GetProgramResourceIndex, (GLuint program, GLenum programInterface, const GLchar *name)) \
    X(GLint, GetProgramResourceLocation, (GLuint program, GLenum programInterface, const GLchar *name)) \
    X(void, GetProgramResourceiv, (GLuint program, GLenum programInterface, GLuint index, GLsizei propCount, const GLenum *props, GLsizei count, GLsizei *length, GLint *params)) \
    X(void, GetProgramInterfaceiv, (GLuint program, GLenum programInterface, GLenum pname, GLint *params))

#define QUADCAST_GL_FUNCTIONS_UNIFORMS(X) \
    X(void, Uniform1i, (GLint location, GLint v0)) \
    X(void, Uniform2i, (GLint location, GLint v0, GLint v1)) \
    X(void, Uniform3i, (GLint location, GLint v0, GLint v1, GLint v2)) \
    X(void, Uniform4i, (GLint location, GLint v0, GLint v1, GLint v2, GLint v3)) \
    X(void, Uniform1ui, (GLint location, GLuint v0)) \
    X(void, Uniform2ui, (GLint location, GLuint v0, GLuint v1)) \
    X(void, Uniform3ui, (GLint location, GLuint v0, GLuint v1, GLuint v2)) \
    X(void, Uniform4ui, (GLint location, GLuint v0, GLuint v1, GLuint v2, GLuint v3)) \
    X(void, Uniform1f, (GLint location, GLfloat v0)) \
    X(void, Uniform2f, (GLint location, GLfloat v0, GLfloat v1)) \
    X(void, Uniform3f, (GLint location, GLfloat v0, GLfloat v1, GLfloat v2)) \
    X(void, Uniform4f, (GLint location, GLfloat v0, GLfloat v1, GLfloat v2, GLfloat v3)) \
    X(void, Uniform1iv, (GLint location, GLsizei count, const GLint *value)) \
    X(void, Uniform1uiv, (GLint location, GLsizei count, const GLuint *value)) \
    X(void, Uniform1fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(void, Uniform2fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(void, Uniform3fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(void, Uniform4fv, (GLint location, GLsizei count, const GLfloat *value)) \
    X(void, Uniform2iv, (GLint location, GLsizei count, const GLint *value)) \
    X(void, Uniform3iv, (GLint location, GLsizei count, const GLint *value)) \
    X(void, Uniform4iv, (GLint location, GLsizei count, const GLint *value)) \
    X(void, Uniform2uiv, (GLint location, GLsizei count, const GLuint *value)) \
    X(void, Uniform3uiv, (GLint location, GLsizei count, const GLuint *value)) \
    X(void, Uniform4uiv, (GLint location, GLsizei count, const GLuint *value)) \
    X(void, UniformMatrix2fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, UniformMatrix3fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, UniformMatrix4fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, UniformMatrix3x4fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, UniformMatrix4x3fv, (GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, ProgramUniform1i, (GLuint program, GLint location, GLint v0)) \
    X(void, ProgramUniform1ui, (GLuint program, GLint location, GLuint v0)) \
    X(void, ProgramUniform1f, (GLuint program, GLint location, GLfloat v0)) \
    X(void, ProgramUniform2f, (GLuint program, GLint location, GLfloat v0, GLfloat v1)) \
    X(void, ProgramUniform3f, (GLuint program, GLint location, GLfloat v0, GLfloat v1, GLfloat v2)) \
    X(void, ProgramUniform4f, (GLuint program, GLint location, GLfloat v0, GLfloat v1, GLfloat v2, GLfloat v3)) \
    X(void, ProgramUniform3fv, (GLuint program, GLint location, GLsizei count, const GLfloat *value)) \
    X(void, ProgramUniform4fv, (GLuint program, GLint location, GLsizei count, const GLfloat *value)) \
    X(void, ProgramUniformMatrix3fv, (GLuint program, GLint location, GLsizei count, GLboolean transpose, const GLfloat *value)) \
    X(void, ProgramUniformMatrix4fv, (GLuint program, GLint location, GLsizei count, GLboolean transpose, const GLfloat *value))

#define QUADCAST_GL_FUNCTIONS_BUFFERS(X) \
    X(void, GenBuffers, (GLsizei n, GLuint *buffers)) \
    X(void, DeleteBuffers, (GLsizei n, const GLuint *buffers)) \
    X(GLboolean, IsBuffer, (GLuint buffer)) \
    X(void, BindBuffer, (GLenum target, GLuint buffer)) \
    X(void, BindBufferBase, (GLenum target, GLuint index, GLuint buffer)) \
    X(void, BindBufferRange, (GLenum target, GLuint index, GLuint buffer, GLintptr offset, GLsizeiptr size)) \
    X(void, BufferData, (GLenum target, GLsizeiptr size, const void *data, GLenum usage)) \
    X(void, BufferSubData, (GLenum target, GLintptr offset, GLsizeiptr size, const void *data)) \
    X(void, ClearBufferData, (GLenum target, GLenum internalformat, GLenum format, GLenum type, const void *data)) \
    X(void, ClearBufferSubData, (GLenum target, GLenum internalformat, GLintptr offset, GLsizeiptr size, GLenum format, GLenum type, const void *data)) \
    X(void, CopyBufferSubData, (GLenum readTarget, GLenum writeTarget, GLintptr readOffset, GLintptr writeOffset, GLsizeiptr size)) \
    X(void *, MapBufferRange, (GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access)) \
    X(void, FlushMappedBufferRange, (GLenum target, GLintptr offset, GLsizeiptr length)) \
    X(GLboolean, UnmapBuffer, (GLenum target)) \
    X(void, GetBufferSubData, (GLenum target, GLintptr offset, GLsizeiptr size, void *data)) \
    X(void, GetBufferParameteriv, (GLenum target, GLenum pname, GLint *params)) \
    X(void, GetBufferParameteri64v, (GLenum target, GLenum pname, GLint64 *params))

#define QUADCAST_GL_FUNCTIONS_COMPUTE(X) \
    X(void, DispatchCompute, (GLuint num_groups_x, GLuint num_groups_y, GLuint num_groups_z)) \
    X(void, DispatchComputeIndirect, (GLintptr indirect)) \
    X(void, MemoryBarrier, (GLbitfield barriers))

#define QUADCAST_GL_FUNCTIONS_VERTEX(X) \
    X(void, GenVertexArrays, (GLsizei n, GLuint *arrays)) \
    X(void, DeleteVertexArrays, (GLsizei n, const GLuint *arrays)) \
    X(void, BindVertexArray, (GLuint array)) \
    X(void, EnableVertexAttribArray, (GLuint index)) \
    X(void, DisableVertexAttribArray, (GLuint index)) \
    X(void, VertexAttribPointer, (GLuint index, GLint size, GLenum type, GLboolean normalized, GLsizei stride, const void *pointer)) \
    X(void, VertexAttribIPointer, (GLuint index, GLint size, GLenum type, GLsizei stride, const void *pointer)) \
    X(void, VertexAttribDivisor, (GLuint index, GLuint divisor)) \
    X(void, VertexAttribBinding, (GLuint attribindex, GLuint bindingindex)) \
    X(void, VertexAttribFormat, (GLuint attribindex, GLint size, GLenum type, GLboolean normalized, GLuint relativeoffset)) \
    X(void, VertexAttribIFormat, (GLuint attribindex, GLint size, GLenum type, GLuint relativeoffset)) \
    X(void, BindVertexBuffer, (GLuint bindingindex, GLuint buffer, GLintptr offset, GLsizei stride)) \
    X(void, VertexBindingDivisor, (GLuint bindingindex, GLuint divisor))

#define QUADCAST_GL_FUNCTIONS_DRAW(X) \
    X(void, DrawArrays, (GLenum mode, GLint first, GLsizei count)) \
    X(void, DrawElements, (GLenum mode, GLsizei count, GLenum type, const void *indices)) \
    X(void, DrawArraysInstanced, (GLenum mode, GLint first, GLsizei count, GLsizei instancecount)) \
    X(void, DrawElementsInstanced, (GLenum mode, GLsizei count, GLenum type, const void *indices, GLsizei instancecount)) \
    X(void, DrawElementsBaseVertex, (GLenum mode, GLsizei count, GLenum type, const void *indices, GLint basevertex)) \
    X(void, DrawElementsInstancedBaseVertex, (GLenum mode, GLsizei count, GLenum type, const void *indices, GLsizei instancecount, GLint basevertex)) \
    X(void, DrawRangeElements, (GLenum mode, GLuint start, GLuint end, GLsizei count, GLenum type, const void *indices)) \
    X(void, DrawArraysIndirect, (GLenum mode, const void *indirect)) \
    X(void, DrawElementsIndirect, (GLenum mode, GLenum type, const void *indirect)) \
    X(void, MultiDrawArraysIndirect, (GLenum mode, const void *indirect, GLsizei drawcount, GLsizei stride)) \
    X(void, MultiDrawElementsIndirect, (GLenum mode, GLenum type, const void *indirect, GLsizei drawcount, GLsizei stride))

#define QUADCAST_GL_FUNCTIONS_TEXTURES(X) \
    X(void, GenTextures, (GLsizei n, GLuint *textures)) \
    X(void, DeleteTextures, (GLsizei n, const GLuint *textures)) \
    X(void, BindTexture, (GLenum target, GLuint texture)) \
    X(void, ActiveTexture, (GLenum texture)) \
    X(void, TexImage1D, (GLenum target, GLint level, GLint internalformat, GLsizei width, GLint border, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexImage2D, (GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height, GLint border, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexImage3D, (GLenum target, GLint level, GLint internalformat, GLsizei width, GLsizei height, GLsizei depth, GLint border, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexSubImage1D, (GLenum target, GLint level, GLint xoffset, GLsizei width, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexSubImage2D, (GLenum target, GLint level, GLint xoffset, GLint yoffset, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexSubImage3D, (GLenum target, GLint level, GLint xoffset, GLint yoffset, GLint zoffset, GLsizei width, GLsizei height, GLsizei depth, GLenum format, GLenum type, const void *pixels)) \
    X(void, TexStorage1D, (GLenum target, GLsizei levels, GLenum internalformat, GLsizei width)) \
    X(void, TexStorage2D, (GLenum target, GLsizei levels, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, TexStorage3D, (GLenum target, GLsizei levels, GLenum internalformat, GLsizei width, GLsizei height, GLsizei depth)) \
    X(void, TexParameteri, (GLenum target, GLenum pname, GLint param)) \
    X(void, TexParameterf, (GLenum target, GLenum pname, GLfloat param)) \
    X(void, TexParameteriv, (GLenum target, GLenum pname, const GLint *params)) \
    X(void, TexParameterfv, (GLenum target, GLenum pname, const GLfloat *params)) \
    X(void, GetTexImage, (GLenum target, GLint level, GLenum format, GLenum type, void *pixels)) \
    X(void, GetTexLevelParameteriv, (GLenum target, GLint level, GLenum pname, GLint *params)) \
    X(void, GenerateMipmap, (GLenum target)) \
    X(void, BindImageTexture, (GLuint unit, GLuint texture, GLint level, GLboolean layered, GLint layer, GLenum access, GLenum format)) \
    X(void, TexBuffer, (GLenum target, GLenum internalformat, GLuint buffer)) \
    X(void, GenSamplers, (GLsizei count, GLuint *samplers)) \
    X(void, DeleteSamplers, (GLsizei count, const GLuint *samplers)) \
    X(void, BindSampler, (GLuint unit, GLuint sampler)) \
    X(void, SamplerParameteri, (GLuint sampler, GLenum pname, GLint param))

#define QUADCAST_GL_FUNCTIONS_FRAMEBUFFERS(X) \
    X(void, GenFramebuffers, (GLsizei n, GLuint *framebuffers)) \
    X(void, DeleteFramebuffers, (GLsizei n, const GLuint *framebuffers)) \
    X(void, BindFramebuffer, (GLenum target, GLuint framebuffer)) \
    X(void, FramebufferTexture, (GLenum target, GLenum attachment, GLuint texture, GLint level)) \
    X(void, FramebufferTexture2D, (GLenum target, GLenum attachment, GLenum textarget, GLuint texture, GLint level)) \
    X(void, FramebufferTextureLayer, (GLenum target, GLenum attachment, GLuint texture, GLint level, GLint layer)) \
    X(void, FramebufferRenderbuffer, (GLenum target, GLenum attachment, GLenum renderbuffertarget, GLuint renderbuffer)) \
    X(GLenum, CheckFramebufferStatus, (GLenum target)) \
    X(void, GetFramebufferAttachmentParameteriv, (GLenum target, GLenum attachment, GLenum pname, GLint *params)) \
    X(void, DrawBuffer, (GLenum buf)) \
    X(void, DrawBuffers, (GLsizei n, const GLenum *bufs)) \
    X(void, ReadBuffer, (GLenum src)) \
    X(void, BlitFramebuffer, (GLint srcX0, GLint srcY0, GLint srcX1, GLint srcY1, GLint dstX0, GLint dstY0, GLint dstX1, GLint dstY1, GLbitfield mask, GLenum filter)) \
    X(void, ClearBufferfv, (GLenum buffer, GLint drawbuffer, const GLfloat *value)) \
    X(void, ClearBufferiv, (GLenum buffer, GLint drawbuffer, const GLint *value)) \
    X(void, ClearBufferuiv, (GLenum buffer, GLint drawbuffer, const GLuint *value)) \
    X(void, ClearBufferfi, (GLenum buffer, GLint drawbuffer, GLfloat depth, GLint stencil)) \
    X(void, GenRenderbuffers, (GLsizei n, GLuint *renderbuffers)) \
    X(void, DeleteRenderbuffers, (GLsizei n, const GLuint *renderbuffers)) \
    X(void, BindRenderbuffer, (GLenum target, GLuint renderbuffer)) \
    X(void, RenderbufferStorage, (GLenum target, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, RenderbufferStorageMultisample, (GLenum target, GLsizei samples, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, ReadPixels, (GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type, void *pixels))

#define QUADCAST_GL_FUNCTIONS_QUERIES(X) \
    X(void, GenQueries, (GLsizei n, GLuint *ids)) \
    X(void, DeleteQueries, (GLsizei n, const GLuint *ids)) \
    X(void, BeginQuery, (GLenum target, GLuint id)) \
    X(void, EndQuery, (GLenum target)) \
    X(void, QueryCounter, (GLuint id, GLenum target)) \
    X(void, GetQueryiv, (GLenum target, GLenum pname, GLint *params)) \
    X(void, GetQueryObjectiv, (GLuint id, GLenum pname, GLint *params)) \
    X(void, GetQueryObjectuiv, (GLuint id, GLenum pname, GLuint *params)) \
    X(void, GetQueryObjecti64v, (GLuint id, GLenum pname, GLint64 *params)) \
    X(void, GetQueryObjectui64v, (GLuint id, GLenum pname, GLuint64 *params)) \
    X(GLsync, FenceSync, (GLenum condition, GLbitfield flags)) \
    X(GLenum, ClientWaitSync, (GLsync sync, GLbitfield flags, GLuint64 timeout)) \
    X(void, WaitSync, (GLsync sync, GLbitfield flags, GLuint64 timeout)) \
    X(void, DeleteSync, (GLsync sync))

#define QUADCAST_GL_FUNCTIONS_DEBUG(X) \
    X(void, DebugMessageCallback, (GLDEBUGPROC callback, const void *userParam)) \
    X(void, DebugMessageControl, (GLenum source, GLenum type, GLenum severity, GLsizei count, const GLuint *ids, GLboolean enabled)) \
    X(void, DebugMessageInsert, (GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length, const GLchar *buf)) \
    X(void, ObjectLabel, (GLenum identifier, GLuint name, GLsizei length, const GLchar *label)) \
    X(void, PushDebugGroup, (GLenum source, GLuint id, GLsizei length, const GLchar *message)) \
    X(void, PopDebugGroup, ())

#define QUADCAST_GL_FUNCTIONS_GL45(X) \
    X(void, BufferStorage, (GLenum target, GLsizeiptr size, const void *data, GLbitfield flags)) \
    X(void, CreateBuffers, (GLsizei n, GLuint *buffers)) \
    X(void, NamedBufferData, (GLuint buffer, GLsizeiptr size, const void *data, GLenum usage)) \
    X(void, NamedBufferSubData, (GLuint buffer, GLintptr offset, GLsizeiptr size, const void *data)) \
    X(void, NamedBufferStorage, (GLuint buffer, GLsizeiptr size, const void *data, GLbitfield flags)) \
    X(void, ClearNamedBufferData, (GLuint buffer, GLenum internalformat, GLenum format, GLenum type, const void *data)) \
    X(void, ClearNamedBufferSubData, (GLuint buffer, GLenum internalformat, GLintptr offset, GLsizeiptr size, GLenum format, GLenum type, const void *data)) \
    X(void, CopyNamedBufferSubData, (GLuint readBuffer, GLuint writeBuffer, GLintptr readOffset, GLintptr writeOffset, GLsizeiptr size)) \
    X(void *, MapNamedBufferRange, (GLuint buffer, GLintptr offset, GLsizeiptr length, GLbitfield access)) \
    X(GLboolean, UnmapNamedBuffer, (GLuint buffer)) \
    X(void, GetNamedBufferSubData, (GLuint buffer, GLintptr offset, GLsizeiptr size, void *data)) \
    X(void, CreateVertexArrays, (GLsizei n, GLuint *arrays)) \
    X(void, VertexArrayVertexBuffer, (GLuint vaobj, GLuint bindingindex, GLuint buffer, GLintptr offset, GLsizei stride)) \
    X(void, VertexArrayElementBuffer, (GLuint vaobj, GLuint buffer)) \
    X(void, VertexArrayAttribFormat, (GLuint vaobj, GLuint attribindex, GLint size, GLenum type, GLboolean normalized, GLuint relativeoffset)) \
    X(void, VertexArrayAttribIFormat, (GLuint vaobj, GLuint attribindex, GLint size, GLenum type, GLuint relativeoffset)) \
    X(void, VertexArrayAttribBinding, (GLuint vaobj, GLuint attribindex, GLuint bindingindex)) \
    X(void, VertexArrayBindingDivisor, (GLuint vaobj, GLuint bindingindex, GLuint divisor)) \
    X(void, EnableVertexArrayAttrib, (GLuint vaobj, GLuint index)) \
    X(void, DisableVertexArrayAttrib, (GLuint vaobj, GLuint index)) \
    X(void, CreateTextures, (GLenum target, GLsizei n, GLuint *textures)) \
    X(void, TextureBuffer, (GLuint texture, GLenum internalformat, GLuint buffer)) \
    X(void, TextureStorage1D, (GLuint texture, GLsizei levels, GLenum internalformat, GLsizei width)) \
    X(void, TextureStorage2D, (GLuint texture, GLsizei levels, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, TextureStorage3D, (GLuint texture, GLsizei levels, GLenum internalformat, GLsizei width, GLsizei height, GLsizei depth)) \
    X(void, TextureSubImage1D, (GLuint texture, GLint level, GLint xoffset, GLsizei width, GLenum format, GLenum type, const void *pixels)) \
    X(void, TextureSubImage2D, (GLuint texture, GLint level, GLint xoffset, GLint yoffset, GLsizei width, GLsizei height, GLenum format, GLenum type, const void *pixels)) \
    X(void, TextureSubImage3D, (GLuint texture, GLint level, GLint xoffset, GLint yoffset, GLint zoffset, GLsizei width, GLsizei height, GLsizei depth, GLenum format, GLenum type, const void *pixels)) \
    X(void, TextureParameteri, (GLuint texture, GLenum pname, GLint param)) \
    X(void, TextureParameterf, (GLuint texture, GLenum pname, GLfloat param)) \
    X(void, GenerateTextureMipmap, (GLuint texture)) \
    X(void, BindTextureUnit, (GLuint unit, GLuint texture)) \
    X(void, TextureBarrier, ()) \
    X(void, GetTextureImage, (GLuint texture, GLint level, GLenum format, GLenum type, GLsizei bufSize, void *pixels)) \
    X(void, CreateFramebuffers, (GLsizei n, GLuint *framebuffers)) \
    X(void, NamedFramebufferTexture, (GLuint framebuffer, GLenum attachment, GLuint texture, GLint level)) \
    X(void, NamedFramebufferRenderbuffer, (GLuint framebuffer, GLenum attachment, GLenum renderbuffertarget, GLuint renderbuffer)) \
    X(void, NamedFramebufferDrawBuffer, (GLuint framebuffer, GLenum buf)) \
    X(void, NamedFramebufferDrawBuffers, (GLuint framebuffer, GLsizei n, const GLenum *bufs)) \
    X(void, NamedFramebufferReadBuffer, (GLuint framebuffer, GLenum src)) \
    X(GLenum, CheckNamedFramebufferStatus, (GLuint framebuffer, GLenum target)) \
    X(void, ClearNamedFramebufferfv, (GLuint framebuffer, GLenum buffer, GLint drawbuffer, const GLfloat *value)) \
    X(void, ClearNamedFramebufferuiv, (GLuint framebuffer, GLenum buffer, GLint drawbuffer, const GLuint *value)) \
    X(void, ClearNamedFramebufferfi, (GLuint framebuffer, GLenum buffer, GLint drawbuffer, GLfloat depth, GLint stencil)) \
    X(void, BlitNamedFramebuffer, (GLuint readFramebuffer, GLuint drawFramebuffer, GLint srcX0, GLint srcY0, GLint srcX1, GLint srcY1, GLint dstX0, GLint dstY0, GLint dstX1, GLint dstY1, GLbitfield mask, GLenum filter)) \
    X(void, CreateRenderbuffers, (GLsizei n, GLuint *renderbuffers)) \
    X(void, NamedRenderbufferStorage, (GLuint renderbuffer, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, NamedRenderbufferStorageMultisample, (GLuint renderbuffer, GLsizei samples, GLenum internalformat, GLsizei width, GLsizei height)) \
    X(void, CreateQueries, (GLenum target, GLsizei n, GLuint *ids)) \
    X(void, CreateSamplers, (GLsizei n, GLuint *samplers)) \
    X(void, ClipControl, (GLenum origin, GLenum depth)) \
    X(void, MemoryBarrierByRegion, (GLbitfield barriers))

/// Every entry point that an OpenGL 4.3 core context must provide.
#define QUADCAST_GL_FUNCTIONS_GL43(X) \
    QUADCAST_GL_FUNCTIONS_STATE(X) \
    QUADCAST_GL_FUNCTIONS_SHADERS(X) \
    QUADCAST_GL_FUNCTIONS_UNIFORMS(X) \
    QUADCAST_GL_FUNCTIONS_BUFFERS(X) \
    QUADCAST_GL_FUNCTIONS_COMPUTE(X) \
    QUADCAST_GL_FUNCTIONS_VERTEX(X) \
    QUADCAST_GL_FUNCTIONS_DRAW(X) \
    QUADCAST_GL_FUNCTIONS_TEXTURES(X) \
    QUADCAST_GL_FUNCTIONS_FRAMEBUFFERS(X) \
    QUADCAST_GL_FUNCTIONS_QUERIES(X) \
    QUADCAST_GL_FUNCTIONS_DEBUG(X)

/// Every entry point of the table.
#define QUADCAST_GL_FUNCTIONS(X) \
    QUADCAST_GL_FUNCTIONS_GL43(X) \
    QUADCAST_GL_FUNCTIONS_GL45(X)

namespace quadcast::gl {

/// Maps a GL function name ("glDispatchCompute") to its address, or to null when the context
/// lacks it: OSMesaGetProcAddress, eglGetProcAddress, glXGetProcAddress, SDL_GL_GetProcAddress ...
using Resolver = std::function<void*(const char*)>;

/// A resolver returned null for entry points the table needs.
class MissingEntryPoints : public std::runtime_error {
public:
    MissingEntryPoints(std::vector<std::string> names, const std::string& message)
        : std::runtime_error(message), names_(std::move(names)) {}
    /// The missing functions, with their "gl" prefix, in table order.
    const std::vector<std::string>& names() const noexcept { return names_; }

private:
    std::vector<std::string> names_;
};

/// A GL call reported errors (glGetError).
class GlError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The table of OpenGL functions quadcast uses, resolved once per context. Members are named
/// like the GL functions without the "gl" prefix: `api.DispatchCompute(n, 1, 1)`.
/// The table belongs to the context it was loaded for (function pointers may differ between
/// contexts on some platforms); load it with that context current.
struct Api {
#define QUADCAST_GL_X_(ret, name, params) ret(APIENTRY* name) params = nullptr;
    QUADCAST_GL_FUNCTIONS(QUADCAST_GL_X_)
#undef QUADCAST_GL_X_

    /// GL_MAJOR_VERSION / GL_MINOR_VERSION of the context it was loaded from.
    int major = 0;
    int minor = 0;
    /// GL_CONTEXT_CORE_PROFILE_BIT is set (a 4.x compatibility context also loads).
    bool core_profile = false;

    /// True when the context is 4.5+ and the QUADCAST_GL_FUNCTIONS_GL45 entries (direct state
    /// access, buffer storage, clip control) are loaded: always, for a loaded Api (load refuses older contexts).
    bool has_gl45() const noexcept { return major > 4 || (major == 4 && minor >= 5); }
    /// 10 * major + minor, e.g. 45.
    int version() const noexcept { return 10 * major + minor; }

    /// Resolves every entry point with `resolve` (the context must be current). Throws
    /// MissingEntryPoints naming every function the resolver returned null for, and
    /// std::runtime_error naming the version found when the context is older than OpenGL 4.5.
    static Api load(const Resolver& resolve);
    static Api load(void* (*resolve)(const char*)) {
        if (resolve == nullptr) throw std::invalid_argument("quadcast::gl::Api::load: null resolver");
        return load(Resolver(resolve));
    }
};

/// "GL_INVALID_OPERATION" etc., or the hex value.
inline std::string error_name(GLenum e) {
    switch (e) {
    case GL_NO_ERROR: return "GL_NO_ERROR";
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    default: {
        char buf[32];
        std::snprintf(buf, sizeof buf, "GL error 0x%04X", static_cast<unsigned>(e));
        return buf;
    }
    }
}

/// Drains glGetError; throws GlError "quadcast::gl: <where>: GL_INVALID_VALUE, ..." if any
/// error was queued. Cheap enough for once per pass; not for every call.
inline void check_errors(const Api& api, std::string_view where) {
    std::string list;
    for (int i = 0; i < 16; ++i) {  // a lost context can return errors forever
        GLenum e = api.GetError();
        if (e == GL_NO_ERROR) break;
        if (!list.empty()) list += ", ";
        list += error_name(e);
    }
    if (!list.empty()) throw GlError("quadcast::gl: " + std::string(where) + ": " + list);
}

/// check_errors only when QUADCAST_GL_DEBUG is defined non-zero or NDEBUG is not defined.
inline void debug_check_errors([[maybe_unused]] const Api& api, [[maybe_unused]] std::string_view where) {
#if (defined(QUADCAST_GL_DEBUG) && QUADCAST_GL_DEBUG) || (!defined(QUADCAST_GL_DEBUG) && !defined(NDEBUG))
    check_errors(api, where);
#endif
}

/// glGetString as std::string ("" when null).
inline std::string get_string(const Api& api, GLenum name) {
    const GLubyte* s = api.GetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

/// glGetIntegerv for a single value.
inline GLint get_integer(const Api& api, GLenum pname) {
    GLint v = 0;
    api.GetIntegerv(pname, &v);
    return v;
}

/// Whether the current context lists the extension `name` (glGetStringi(GL_EXTENSIONS, i)).
inline bool has_extension(const Api& api, std::string_view name) {
    const GLint n = get_integer(api, GL_NUM_EXTENSIONS);
    for (GLint i = 0; i < n; ++i) {
        const GLubyte* e = api.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i));
        if (e && name == reinterpret_cast<const char*>(e)) return true;
    }
    return false;
}

inline Api Api::load(const Resolver& resolve) {
    if (!resolve) throw std::invalid_argument("quadcast::gl::Api::load: empty resolver");
    Api api;
    std::vector<std::string> missing;
    auto get = [&](auto& slot, const char* name) {
        void* p = resolve(name);
        if (p == nullptr) missing.emplace_back(name);
        // Object-to-function pointer conversion: conditionally supported, fine on POSIX.
        slot = reinterpret_cast<std::remove_reference_t<decltype(slot)>>(p);
    };
    auto fail = [&](const char* what) {
        std::string msg = "quadcast::gl: the OpenGL context does not provide ";
        for (std::size_t i = 0; i < missing.size(); ++i) msg += (i ? ", " : "") + missing[i];
        msg += std::string(" (the resolver returned null; ") + what + ")";
        throw MissingEntryPoints(missing, msg);
    };
#define QUADCAST_GL_X_(ret, name, params) get(api.name, "gl" #name);
    QUADCAST_GL_FUNCTIONS_GL43(QUADCAST_GL_X_)
    if (!missing.empty()) fail("quadcast needs an OpenGL 4.5 core context");

    api.major = get_integer(api, GL_MAJOR_VERSION);
    api.minor = get_integer(api, GL_MINOR_VERSION);
    GLint mask = get_integer(api, GL_CONTEXT_PROFILE_MASK);
    api.core_profile = (mask & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
    for (int i = 0; i < 16 && api.GetError() != GL_NO_ERROR; ++i) {}  // pre-3.2 rejects the profile query
    if (api.version() < 45) {
        // Every generated stage is `#version 450` and the renderers bind with direct state access.
        std::string ver = get_string(api, GL_VERSION);
        throw std::runtime_error("quadcast::gl: the current context is OpenGL " + std::to_string(api.major) + "." +
                                 std::to_string(api.minor) + " (\"" + ver + "\"); quadcast needs OpenGL 4.5 (GLSL 4.50, direct state access)");
    }
    QUADCAST_GL_FUNCTIONS_GL45(QUADCAST_GL_X_)
    if (!missing.empty()) fail("the context reports OpenGL 4.5 but lacks these 4.4/4.5 functions");
#undef QUADCAST_GL_X_
    return api;
}

/// What a context reports about itself; filled by describe_context().
struct ContextInfo {
    int major = 0, minor = 0;  ///< GL_MAJOR_VERSION, GL_MINOR_VERSION
    bool core_profile = false;
    std::string version;   ///< GL_VERSION, e.g. "4.5 (Core Profile) Mesa 22.3.6"
    std::string renderer;  ///< GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string vendor;    ///< GL_VENDOR
    std::string glsl;      ///< GL_SHADING_LANGUAGE_VERSION
    std::string backend;   ///< "OSMesa" or "EGL surfaceless"
    /// Empty, or why the context is older than requested ("requested 4.5, got 4.3").
    std::string fallback;

    /// One line: "OpenGL 4.5 core (4.5 (Core Profile) Mesa 22.3.6) on llvmpipe (...) via OSMesa".
    std::string summary() const {
        std::string s = "OpenGL " + std::to_string(major) + "." + std::to_string(minor) +
                        (core_profile ? " core" : " compatibility") + " (" + version + ") on " + renderer + " via " +
                        backend;
        if (!fallback.empty()) s += " [" + fallback + "]";
        return s;
    }
};

/// Reads version, renderer ... from the current context through `api`.
inline ContextInfo describe_context(const Api& api, std::string backend) {
    ContextInfo info;
    info.major = api.major;
    info.minor = api.minor;
    info.core_profile = api.core_profile;
    info.version = get_string(api, GL_VERSION);
    info.renderer = get_string(api, GL_RENDERER);
    info.vendor = get_string(api, GL_VENDOR);
    info.glsl = get_string(api, GL_SHADING_LANGUAGE_VERSION);
    info.backend = std::move(backend);
    return info;
}

}  // namespace quadcast::gl
