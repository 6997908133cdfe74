/* gl_context.c - GLFW window or EGL surfaceless offscreen context (see gl_context.h). */
#include "gl_context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct tp_gl_context {
    int w, h;
    /* offscreen */
    EGLDisplay dpy;
    EGLContext ctx;
    GLuint fbo, color, depth;
    /* multisampling: the frames' target, resolved into the one above (or the window's) */
    int samples;
    GLuint ms_fbo, ms_color, ms_depth;
    int ms_w, ms_h;
    /* window */
    GLFWwindow* win;
};

/* Keeps the driver's per-frame memory in the heap between frames. A software rasteriser
 * (llvmpipe) bins each frame's triangles into tens of MB of malloc'd blocks and frees them at the
 * end of the frame. glibc returns the top of the heap to the system when more than
 * M_TRIM_THRESHOLD is free there (128 KB unless the process has already freed a large mapped
 * block, which raises it to up to 64 MB): the next frame then faults every page in again. A
 * process that loaded a DEM had raised it (the DEM path); a store's viewer had not, and paid
 * 4,500 page faults per frame (18 MB; measured in docs/PERFORMANCE.md, "the draw"). These are
 * the values glibc's own dynamic rule reaches, set from the start. */
static void keep_frame_memory(void)
{
#ifdef __GLIBC__
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
}

int tp_gl_context_create_headless(int w, int h, tp_gl_context** out, tp_error* err)
{
    tp_gl_context* c = calloc(1, sizeof *c);
    if (!c) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return 0;
    }
    c->w = w;
    c->h = h;
    c->dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    EGLint major, minor, count = 0;
    EGLConfig cfg = NULL;
    static const EGLint cfg_attr[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE,
                                      EGL_OPENGL_BIT, EGL_NONE};
    static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    if (c->dpy == EGL_NO_DISPLAY || !eglInitialize(c->dpy, &major, &minor) ||
        !eglBindAPI(EGL_OPENGL_API)) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "no EGL surfaceless display (is Mesa's libegl-mesa0 installed?)");
        free(c);
        return 0;
    }
    eglChooseConfig(c->dpy, cfg_attr, &cfg, 1, &count);
    c->ctx = eglCreateContext(c->dpy, count ? cfg : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attr);
    if (c->ctx == EGL_NO_CONTEXT ||
        !eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx)) {
        tp_error_set(err, TP_ERR_BACKEND, "no OpenGL 3.3 core context through EGL (error 0x%x)",
                     (unsigned)eglGetError());
        if (c->ctx != EGL_NO_CONTEXT)
            eglDestroyContext(c->dpy, c->ctx);
        eglTerminate(c->dpy);
        free(c);
        return 0;
    }
    keep_frame_memory();
    glGenFramebuffers(1, &c->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, c->fbo);
    glGenRenderbuffers(1, &c->color);
    glBindRenderbuffer(GL_RENDERBUFFER, c->color);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->color);
    glGenRenderbuffers(1, &c->depth);
    glBindRenderbuffer(GL_RENDERBUFFER, c->depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, c->depth);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        tp_error_set(err, TP_ERR_BACKEND, "offscreen framebuffer %dx%d is incomplete", w, h);
        tp_gl_context_destroy(c);
        return 0;
    }
    *out = c;
    return 1;
}

int tp_gl_context_create_window(int w, int h, const char* title, tp_gl_context** out, tp_error* err)
{
    if (!glfwInit()) {
        const char* why = NULL;
        glfwGetError(&why);
        tp_error_set(err, TP_ERR_BACKEND, "no display to open a window on (%s); use --headless",
                     why ? why : "glfwInit failed");
        return 0;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SAMPLES, 0); /* multisampled in a framebuffer of ours: --msaa */
    GLFWwindow* win = glfwCreateWindow(w, h, title, NULL, NULL);
    if (!win) {
        const char* why = NULL;
        glfwGetError(&why);
        tp_error_set(err, TP_ERR_BACKEND, "cannot open a %dx%d OpenGL 3.3 window (%s)", w, h,
                     why ? why : "unknown reason");
        glfwTerminate();
        return 0;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(1);
    keep_frame_memory();
    tp_gl_context* c = calloc(1, sizeof *c);
    if (!c) {
        glfwDestroyWindow(win);
        glfwTerminate();
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return 0;
    }
    c->win = win;
    c->w = w;
    c->h = h;
    *out = c;
    return 1;
}

static void ms_release(tp_gl_context* c)
{
    if (c->ms_fbo)
        glDeleteFramebuffers(1, &c->ms_fbo);
    if (c->ms_color)
        glDeleteRenderbuffers(1, &c->ms_color);
    if (c->ms_depth)
        glDeleteRenderbuffers(1, &c->ms_depth);
    c->ms_fbo = c->ms_color = c->ms_depth = 0;
    c->ms_w = c->ms_h = 0;
}

/* (Re)makes the multisampled framebuffer at the context's size; 0 when it is incomplete. */
static int ms_make(tp_gl_context* c)
{
    ms_release(c);
    glGenFramebuffers(1, &c->ms_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, c->ms_fbo);
    glGenRenderbuffers(1, &c->ms_color);
    glBindRenderbuffer(GL_RENDERBUFFER, c->ms_color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, GL_RGBA8, c->w, c->h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, c->ms_color);
    glGenRenderbuffers(1, &c->ms_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, c->ms_depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, c->samples, GL_DEPTH_COMPONENT24, c->w,
                                     c->h);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, c->ms_depth);
    c->ms_w = c->w;
    c->ms_h = c->h;
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

int tp_gl_context_set_msaa(tp_gl_context* c, int samples, tp_error* err)
{
    GLint max = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &max);
    samples = samples > max ? max : samples;
    c->samples = samples > 1 ? samples : 0;
    if (!c->samples) {
        ms_release(c);
    } else if (!ms_make(c)) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "a %dx%d framebuffer of %d samples a pixel is incomplete (drawn without "
                     "multisampling)",
                     c->w, c->h, c->samples);
        ms_release(c);
        c->samples = 0;
        glBindFramebuffer(GL_FRAMEBUFFER, c->win ? 0 : c->fbo);
        return -1;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, c->win ? 0 : c->fbo);
    return c->samples;
}

int tp_gl_context_msaa(const tp_gl_context* c)
{
    return c->samples;
}

int tp_gl_context_software(void)
{
    const char* r = (const char*)glGetString(GL_RENDERER);
    static const char* const soft[] = {"llvmpipe", "softpipe", "swrast", "Software",
                                       "SwiftShader", "GDI Generic"};
    for (size_t i = 0; r && i < sizeof soft / sizeof soft[0]; i++)
        if (strstr(r, soft[i]))
            return 1;
    return 0;
}

int tp_gl_context_default_msaa(void)
{
    return tp_gl_context_software() ? 0 : 4;
}

/* Resolves the multisampled frame into the single-sampled target (the window's or the FBO). */
static void ms_resolve(tp_gl_context* c)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, c->ms_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, c->win ? 0 : c->fbo);
    glBlitFramebuffer(0, 0, c->w, c->h, 0, 0, c->w, c->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, c->ms_fbo);
}

void tp_gl_context_destroy(tp_gl_context* c)
{
    if (!c)
        return;
    ms_release(c);
    if (c->win) {
        glfwDestroyWindow(c->win);
        glfwTerminate();
    } else {
        glDeleteFramebuffers(1, &c->fbo);
        glDeleteRenderbuffers(1, &c->color);
        glDeleteRenderbuffers(1, &c->depth);
        eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(c->dpy, c->ctx);
        eglTerminate(c->dpy);
    }
    free(c);
}

void tp_gl_context_begin_frame(tp_gl_context* c)
{
    if (c->win)
        glfwGetFramebufferSize(c->win, &c->w, &c->h);
    if (c->samples && (c->ms_w != c->w || c->ms_h != c->h) && !ms_make(c)) {
        ms_release(c); /* a window grown past what the driver holds: drawn without */
        c->samples = 0;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, c->samples ? c->ms_fbo : c->win ? 0 : c->fbo);
    glViewport(0, 0, c->w, c->h);
}

void tp_gl_context_end_frame(tp_gl_context* c)
{
    if (c->samples)
        ms_resolve(c);
    if (c->win)
        glfwSwapBuffers(c->win);
}

void tp_gl_context_size(const tp_gl_context* c, int* w, int* h)
{
    *w = c->w;
    *h = c->h;
}

void tp_gl_context_read_rgba(tp_gl_context* c, uint8_t* rgba)
{
    if (c->samples)
        ms_resolve(c);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, c->win ? 0 : c->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, c->w, c->h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    /* GL's rows go bottom-up; images go top-down. */
    size_t row = (size_t)c->w * 4;
    uint8_t* tmp = malloc(row);
    if (!tmp)
        return;
    for (int y = 0; y < c->h / 2; y++) {
        uint8_t* a = rgba + (size_t)y * row;
        uint8_t* b = rgba + (size_t)(c->h - 1 - y) * row;
        memcpy(tmp, a, row);
        memcpy(a, b, row);
        memcpy(b, tmp, row);
    }
    free(tmp);
}

static GLuint compile(GLenum type, const char* src, tp_error* err)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        tp_error_set(err, TP_ERR_BACKEND, "shader does not compile: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

unsigned int tp_gl_program(const char* vertex_src, const char* fragment_src, tp_error* err)
{
    GLuint vs = compile(GL_VERTEX_SHADER, vertex_src, err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, fragment_src, err) : 0;
    if (!fs) {
        glDeleteShader(vs);
        return 0;
    }
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        tp_error_set(err, TP_ERR_BACKEND, "shaders do not link");
        glDeleteProgram(prog);
        return 0;
    }
    return prog;
}

void* tp_gl_context_window(const tp_gl_context* c)
{
    return c->win;
}
