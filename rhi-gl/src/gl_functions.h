// The GL entry points the backend calls, loaded through the platform's getProcAddress. A table
// per device (not global function pointers) because EGL and OSMesa hand out different entry
// points and both may be alive in one process. libepoxy cannot load through OSMesa.
#pragma once

#include <GL/glcorearb.h>

namespace janus::rhi::gl {

class Platform;

// Entry points every context we accept has (GL 4.3 core and GLES 3.0 alike).
#define JANUS_GL_REQUIRED_FUNCTIONS(X)                                                          \
    X(PFNGLGETERRORPROC, glGetError)                                                                          \
    X(PFNGLGETSTRINGPROC, glGetString)                                                                        \
    X(PFNGLGETSTRINGIPROC, glGetStringi)                                                                      \
    X(PFNGLGETINTEGERVPROC, glGetIntegerv)                                                                    \
    X(PFNGLGETINTEGER64VPROC, glGetInteger64v)                                                                \
    X(PFNGLGETINTEGERI_VPROC, glGetIntegeri_v)                                                                \
    X(PFNGLGETFLOATVPROC, glGetFloatv)                                                                        \
    X(PFNGLENABLEPROC, glEnable)                                                                              \
    X(PFNGLDISABLEPROC, glDisable)                                                                            \
    X(PFNGLVIEWPORTPROC, glViewport)                                                                          \
    X(PFNGLSCISSORPROC, glScissor)                                                                            \
    X(PFNGLDEPTHRANGEFPROC, glDepthRangef)                                                                    \
    X(PFNGLDEPTHFUNCPROC, glDepthFunc)                                                                        \
    X(PFNGLDEPTHMASKPROC, glDepthMask)                                                                        \
    X(PFNGLCOLORMASKPROC, glColorMask)                                                                        \
    X(PFNGLCULLFACEPROC, glCullFace)                                                                          \
    X(PFNGLFRONTFACEPROC, glFrontFace)                                                                        \
    X(PFNGLPOLYGONOFFSETPROC, glPolygonOffset)                                                                \
    X(PFNGLBLENDFUNCSEPARATEPROC, glBlendFuncSeparate)                                                        \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, glBlendEquationSeparate)                                                \
    X(PFNGLPIXELSTOREIPROC, glPixelStorei)                                                                    \
    X(PFNGLFINISHPROC, glFinish)                                                                              \
    X(PFNGLFLUSHPROC, glFlush)                                                                                \
    X(PFNGLGENBUFFERSPROC, glGenBuffers)                                                                      \
    X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                                                                \
    X(PFNGLBINDBUFFERPROC, glBindBuffer)                                                                      \
    X(PFNGLBUFFERDATAPROC, glBufferData)                                                                      \
    X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                                                                \
    X(PFNGLMAPBUFFERRANGEPROC, glMapBufferRange)                                                              \
    X(PFNGLUNMAPBUFFERPROC, glUnmapBuffer)                                                                    \
    X(PFNGLCOPYBUFFERSUBDATAPROC, glCopyBufferSubData)                                                        \
    X(PFNGLBINDBUFFERRANGEPROC, glBindBufferRange)                                                            \
    X(PFNGLGENTEXTURESPROC, glGenTextures)                                                                    \
    X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                                                              \
    X(PFNGLBINDTEXTUREPROC, glBindTexture)                                                                    \
    X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                                                                \
    X(PFNGLTEXSTORAGE2DPROC, glTexStorage2D)                                                                  \
    X(PFNGLTEXSTORAGE3DPROC, glTexStorage3D)                                                                  \
    X(PFNGLTEXSUBIMAGE2DPROC, glTexSubImage2D)                                                                \
    X(PFNGLTEXSUBIMAGE3DPROC, glTexSubImage3D)                                                                \
    X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                                                                \
    X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap)                                                              \
    X(PFNGLGENSAMPLERSPROC, glGenSamplers)                                                                    \
    X(PFNGLDELETESAMPLERSPROC, glDeleteSamplers)                                                              \
    X(PFNGLBINDSAMPLERPROC, glBindSampler)                                                                    \
    X(PFNGLSAMPLERPARAMETERIPROC, glSamplerParameteri)                                                        \
    X(PFNGLSAMPLERPARAMETERFPROC, glSamplerParameterf)                                                        \
    X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                                                            \
    X(PFNGLDELETEFRAMEBUFFERSPROC, glDeleteFramebuffers)                                                      \
    X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                                                            \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)                                                  \
    X(PFNGLFRAMEBUFFERTEXTURELAYERPROC, glFramebufferTextureLayer)                                            \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)                                              \
    X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                                                                    \
    X(PFNGLREADBUFFERPROC, glReadBuffer)                                                                      \
    X(PFNGLREADPIXELSPROC, glReadPixels)                                                                      \
    X(PFNGLCLEARBUFFERFVPROC, glClearBufferfv)                                                                \
    X(PFNGLCLEARBUFFERUIVPROC, glClearBufferuiv)                                                              \
    X(PFNGLBLITFRAMEBUFFERPROC, glBlitFramebuffer)                                                            \
    X(PFNGLGENRENDERBUFFERSPROC, glGenRenderbuffers)                                                          \
    X(PFNGLDELETERENDERBUFFERSPROC, glDeleteRenderbuffers)                                                    \
    X(PFNGLBINDRENDERBUFFERPROC, glBindRenderbuffer)                                                          \
    X(PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC, glRenderbufferStorageMultisample)                              \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, glFramebufferRenderbuffer)                                            \
    X(PFNGLGETINTERNALFORMATIVPROC, glGetInternalformativ)                                                    \
    X(PFNGLCREATESHADERPROC, glCreateShader)                                                                  \
    X(PFNGLDELETESHADERPROC, glDeleteShader)                                                                  \
    X(PFNGLSHADERSOURCEPROC, glShaderSource)                                                                  \
    X(PFNGLCOMPILESHADERPROC, glCompileShader)                                                                \
    X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                                                    \
    X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                                                          \
    X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                                                                \
    X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                                                                \
    X(PFNGLATTACHSHADERPROC, glAttachShader)                                                                  \
    X(PFNGLDETACHSHADERPROC, glDetachShader)                                                                  \
    X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                                                    \
    X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                                                                  \
    X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                                                        \
    X(PFNGLUSEPROGRAMPROC, glUseProgram)                                                                      \
    X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)                                                      \
    X(PFNGLGETACTIVEUNIFORMPROC, glGetActiveUniform)                                                          \
    X(PFNGLGETUNIFORMIVPROC, glGetUniformiv)                                                                  \
    X(PFNGLGETSAMPLERPARAMETERIVPROC, glGetSamplerParameteriv)                                                \
    X(PFNGLUNIFORM1IPROC, glUniform1i)                                                                        \
    X(PFNGLUNIFORM1UIPROC, glUniform1ui)                                                                      \
    X(PFNGLGETUNIFORMBLOCKINDEXPROC, glGetUniformBlockIndex)                                                  \
    X(PFNGLUNIFORMBLOCKBINDINGPROC, glUniformBlockBinding)                                                    \
    X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                                                            \
    X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                                                      \
    X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                                                            \
    X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                                                    \
    X(PFNGLVERTEXATTRIBIPOINTERPROC, glVertexAttribIPointer)                                                  \
    X(PFNGLVERTEXATTRIBDIVISORPROC, glVertexAttribDivisor)                                                    \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)                                            \
    X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, glDisableVertexAttribArray)                                          \
    X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                                                      \
    X(PFNGLDRAWELEMENTSPROC, glDrawElements)                                                                  \
    X(PFNGLDRAWARRAYSINSTANCEDPROC, glDrawArraysInstanced)                                                    \
    X(PFNGLDRAWELEMENTSINSTANCEDPROC, glDrawElementsInstanced)                                                \
    X(PFNGLGENQUERIESPROC, glGenQueries)                                                                      \
    X(PFNGLDELETEQUERIESPROC, glDeleteQueries)

// Desktop-only entry points, with the name of the ES extension function that stands in for them
// (nullptr: not loaded on ES). Names are never probed: glvnd's eglGetProcAddress returns a stub
// for ANY gl* name, so a non-null pointer proves nothing. Capabilities decide, from the version
// and extension strings, which of these are ever called.
#define JANUS_GL_OPTIONAL_FUNCTIONS(X)                                                          \
    X(PFNGLSHADERSTORAGEBLOCKBINDINGPROC, glShaderStorageBlockBinding, nullptr)                               \
    X(PFNGLGETPROGRAMRESOURCEINDEXPROC, glGetProgramResourceIndex, nullptr)                                   \
    X(PFNGLDISPATCHCOMPUTEPROC, glDispatchCompute, nullptr)                                                   \
    X(PFNGLMEMORYBARRIERPROC, glMemoryBarrier, nullptr)                                                       \
    X(PFNGLBINDIMAGETEXTUREPROC, glBindImageTexture, nullptr)                                                 \
    X(PFNGLCOPYIMAGESUBDATAPROC, glCopyImageSubData, nullptr)                                                 \
    X(PFNGLDRAWARRAYSINSTANCEDBASEINSTANCEPROC, glDrawArraysInstancedBaseInstance, nullptr)                   \
    X(PFNGLDRAWELEMENTSINSTANCEDBASEVERTEXBASEINSTANCEPROC, glDrawElementsInstancedBaseVertexBaseInstance, nullptr) \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, glDrawElementsBaseVertex, nullptr)                                     \
    X(PFNGLQUERYCOUNTERPROC, glQueryCounter, "glQueryCounterEXT")                                             \
    X(PFNGLGETQUERYOBJECTUI64VPROC, glGetQueryObjectui64v, "glGetQueryObjectui64vEXT")                        \
    X(PFNGLDEBUGMESSAGECALLBACKPROC, glDebugMessageCallback, "glDebugMessageCallbackKHR")                     \
    X(PFNGLDEBUGMESSAGECONTROLPROC, glDebugMessageControl, "glDebugMessageControlKHR")                        \
    X(PFNGLDEBUGMESSAGEINSERTPROC, glDebugMessageInsert, "glDebugMessageInsertKHR")                           \
    X(PFNGLPUSHDEBUGGROUPPROC, glPushDebugGroup, "glPushDebugGroupKHR")                                       \
    X(PFNGLPOPDEBUGGROUPPROC, glPopDebugGroup, "glPopDebugGroupKHR")                                          \
    X(PFNGLOBJECTLABELPROC, glObjectLabel, "glObjectLabelKHR")                                                \
    X(PFNGLENABLEIPROC, glEnablei, nullptr)                                                                   \
    X(PFNGLDISABLEIPROC, glDisablei, nullptr)                                                                 \
    X(PFNGLBLENDFUNCSEPARATEIPROC, glBlendFuncSeparatei, nullptr)                                             \
    X(PFNGLBLENDEQUATIONSEPARATEIPROC, glBlendEquationSeparatei, nullptr)                                     \
    X(PFNGLCOLORMASKIPROC, glColorMaski, nullptr) \
    X(PFNGLCLIPCONTROLPROC, glClipControl, "glClipControlEXT")                                                \
    X(PFNGLCLEARTEXIMAGEPROC, glClearTexImage, "glClearTexImageEXT")                                          \
    X(PFNGLCLEARBUFFERDATAPROC, glClearBufferData, nullptr)                                                   \
    X(PFNGLTEXTUREVIEWPROC, glTextureView, nullptr)

struct GLFunctions {
#define JANUS_GL_DECLARE(type, name) type name = nullptr;
#define JANUS_GL_DECLARE_OPTIONAL(type, name, esName) type name = nullptr;
    JANUS_GL_REQUIRED_FUNCTIONS(JANUS_GL_DECLARE)
    JANUS_GL_OPTIONAL_FUNCTIONS(JANUS_GL_DECLARE_OPTIONAL)
#undef JANUS_GL_DECLARE_OPTIONAL
#undef JANUS_GL_DECLARE

    // Throws Error(BackendUnavailable) naming the first required entry point that is missing.
    // `es`: load the optional entry points by their ES extension names.
    void load(const Platform& platform, bool es);
};

}  // namespace janus::rhi::gl
