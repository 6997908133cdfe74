/*
 * gl_context.h - an OpenGL 3.3 core context: a GLFW window, or offscreen through EGL on Mesa's
 * surfaceless platform (no X server, no default framebuffer: an RGBA8 + depth framebuffer object
 * is the target). The only file that knows about GLFW and EGL.
 */
#ifndef TP_APP_GL_CONTEXT_H
#define TP_APP_GL_CONTEXT_H

#include "tp_core.h"

#include <stddef.h>
#include <stdint.h>

typedef struct tp_gl_context tp_gl_context;

/* Both constructors also fix glibc's malloc thresholds for the process (M_MMAP_THRESHOLD 32 MB,
 * M_TRIM_THRESHOLD 64 MB): a software GL driver frees and mallocs its whole binned frame every
 * frame, which glibc would otherwise return to the system and fault in again (gl_context.c). */
/* Offscreen w x h context; no multisampling (tp_gl_context_set_msaa). Returns 0 with err on
 * failure. */
int tp_gl_context_create_headless(int w, int h, tp_gl_context** out, tp_error* err);
/* A window with a 3.3 core context. Returns 0 with err (e.g. no display) on failure. */
int tp_gl_context_create_window(int w, int h, const char* title, tp_gl_context** out,
                                tp_error* err);
void tp_gl_context_destroy(tp_gl_context* c);

/* Binds the frame's target (the FBO offscreen) and sets the viewport to the current size. */
void tp_gl_context_begin_frame(tp_gl_context* c);
/* Shows the frame (swaps a window's buffers; nothing offscreen). */
void tp_gl_context_end_frame(tp_gl_context* c);
void tp_gl_context_size(const tp_gl_context* c, int* w, int* h);
/* Reads the last frame as RGBA8, top row first, into w * h * 4 bytes. */
void tp_gl_context_read_rgba(tp_gl_context* c, uint8_t* rgba);
/* Compiles and links a vertex + fragment shader program in the current context. Returns the
 * program name, or 0 with the compiler's log in err. */
unsigned int tp_gl_program(const char* vertex_src, const char* fragment_src, tp_error* err);

/* Multisampling (--msaa): frames are drawn into a framebuffer of `samples` samples a pixel
 * (GL_RGBA8 and a 24-bit depth, renderbuffers), resolved into the window's or the offscreen
 * target when a frame ends (tp_gl_context_end_frame) or is read (tp_gl_context_read_rgba); a
 * window's is remade when its size changes. samples 0 or 1: none (the default of both
 * constructors); more than GL_MAX_SAMPLES: GL_MAX_SAMPLES. Returns the samples in use (0 for
 * none), or -1 with err when the framebuffer cannot be made (then none). */
int tp_gl_context_set_msaa(tp_gl_context* c, int samples, tp_error* err);
int tp_gl_context_msaa(const tp_gl_context* c); /* samples in use, 0 for none */

/* 1 when the context's renderer (GL_RENDERER) rasterises in software: Mesa's llvmpipe, softpipe
 * or swrast, SwiftShader, Microsoft's GDI; else 0 (a GPU). */
int tp_gl_context_software(void);

/* The samples --msaa means by default: 4 on a GPU, none (0) on a software renderer, where 4
 * samples cost a multiple of the frame (docs/PERFORMANCE.md, "Multisampling"). */
int tp_gl_context_default_msaa(void);

/* The GLFWwindow* of a window context, NULL offscreen. */
void* tp_gl_context_window(const tp_gl_context* c);

#endif
