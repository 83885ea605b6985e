/* rj_render.c - see rj_render.h. */
/* POSIX for open, fstat, lstat and unlink: a failed PNG write removes only a file it made */
#define _POSIX_C_SOURCE 200809L
#include "rj_render.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <math.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef RJR_PNG_ONLY
/* PNG and comparison functions only: no OpenGL, no revjoint (used by pngdiff). */
#elif defined(RJ_RENDER_EGL)
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#else
/* OSMesa is opened at run time (dlopen) by the first rjr_create: its headers give the
   types and constants only, and the program does not link it (see rjr_osm below). */
#include <GL/osmesa.h>
#include <GL/glext.h>
#include <dlfcn.h>
#include <pthread.h>
#endif

#include <png.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static void set_err(char *err, size_t errlen, const char *msg)
{
    if (err && errlen) {
        strncpy(err, msg, errlen - 1);
        err[errlen - 1] = 0;
    }
}

#ifndef RJR_PNG_ONLY
#define RJR_BATCH 24576            /* vertices per draw call (multiple of 3) */
#define RJR_MAX_DIM 16384
#define COL_INK 0x262626u            /* text and dark lines */

struct rjr_context {
    int width, height;
    int samples;
    GLuint fbo_ms, rb_ms;          /* multisample target (samples > 1) */
    GLuint fbo_rs, rb_rs;          /* single-sample resolve target, read back from here */
#ifdef RJ_RENDER_EGL
    EGLDisplay dpy;
    EGLContext egl;
#else
    OSMesaContext osm;
    unsigned char *osm_buf;        /* default framebuffer memory (required by OSMesa) */
#endif
    float *vxy;                    /* triangle batch: 2 floats and 4 bytes per vertex */
    unsigned char *vcol;
    int nv;
    double *pa, *pb, *pc;          /* scratch point buffers (x, y pairs) */
    size_t capa, capb, capc;       /* in points */
    double *po, *pl;               /* frame overlays: per-link stack offsets, joint label boxes */
    size_t capo, capl;             /* in points (a label box takes two) */
    unsigned char *readbuf;        /* RGBA read-back buffer */
    int in_frame, has_frame, failed;
    char err[256];
    char renderer[160], version[160];
};

static void ctx_fail(rjr_context *c, const char *msg)
{
    if (!c->failed) set_err(c->err, sizeof c->err, msg);
    c->failed = 1;
}

static int grow(double **buf, size_t *cap, size_t npts)
{
    double *nb;
    size_t nc;
    if (npts <= *cap) return 0;
    nc = *cap ? *cap : 256;
    while (nc < npts) nc *= 2;
    nb = (double *)realloc(*buf, nc * 2 * sizeof(double));
    if (!nb) return -1;
    *buf = nb;
    *cap = nc;
    return 0;
}

/* ---- Backend: the only code that knows OSMesa / EGL ---------------------------------- */

#ifdef RJ_RENDER_EGL
static int be_create(rjr_context *c, char *err, size_t errlen)
{
    static const EGLint attr[] = { EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE };
    EGLint major, minor;
    c->dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (c->dpy == EGL_NO_DISPLAY) { set_err(err, errlen, "eglGetPlatformDisplay(surfaceless) failed"); return -1; }
    if (!eglInitialize(c->dpy, &major, &minor)) { set_err(err, errlen, "eglInitialize failed"); return -1; }
    if (!eglBindAPI(EGL_OPENGL_API)) { set_err(err, errlen, "eglBindAPI(EGL_OPENGL_API) failed"); eglTerminate(c->dpy); return -1; }
    c->egl = eglCreateContext(c->dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attr);
    if (c->egl == EGL_NO_CONTEXT) { set_err(err, errlen, "eglCreateContext failed"); eglTerminate(c->dpy); return -1; }
    if (!eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->egl)) {
        set_err(err, errlen, "eglMakeCurrent(surfaceless) failed");
        eglDestroyContext(c->dpy, c->egl);
        eglTerminate(c->dpy);
        return -1;
    }
    return 0;
}
static int be_make_current(rjr_context *c)
{
    if (eglGetCurrentContext() == c->egl) return 0;
    return eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->egl) ? 0 : -1;
}
static int be_resize(rjr_context *c) { return be_make_current(c); }
static void be_destroy(rjr_context *c)
{
    eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(c->dpy, c->egl);
    /* eglTerminate would also end other contexts on the shared display; leave it. */
}
static const char *be_name(void) { return "egl-surfaceless"; }
/* EGL is linked: nothing to load */
int rjr_available(char *err, size_t errlen) { set_err(err, errlen, ""); return 0; }
#else
/* OSMesa, loaded on first use. Linking libOSMesa would load it, and with it LLVM, in every
   program that has the renderer, drawing or not (about 30 ms and 50 MB at start-up here),
   so it is opened with dlopen by the first rjr_create and the functions the renderer
   calls are looked up once into this table. libOSMesa exports every GL entry point
   itself (dlsym finds them; OSMesaGetProcAddress is asked for any it would not). The
   library stays loaded to the end of the process (LLVM does not like being unloaded).
   RJ_OSMESA in the environment names another library file to open instead (tests use it
   to see the message when OSMesa is missing). The table is written once, under
   pthread_once, and only read afterwards. */
typedef struct rjr_osm_api {
    OSMesaContext (GLAPIENTRY *CreateContextExt)(GLenum, GLint, GLint, GLint, OSMesaContext);
    GLboolean (GLAPIENTRY *MakeCurrent)(OSMesaContext, void *, GLenum, GLsizei, GLsizei);
    OSMesaContext (GLAPIENTRY *GetCurrentContext)(void);
    void (GLAPIENTRY *DestroyContext)(OSMesaContext);
    void (GLAPIENTRY *BindFramebuffer)(GLenum, GLuint);
    void (GLAPIENTRY *BindRenderbuffer)(GLenum, GLuint);
    void (GLAPIENTRY *BlitFramebuffer)(GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLint, GLbitfield, GLenum);
    GLenum (GLAPIENTRY *CheckFramebufferStatus)(GLenum);
    void (GLAPIENTRY *Clear)(GLbitfield);
    void (GLAPIENTRY *ClearColor)(GLclampf, GLclampf, GLclampf, GLclampf);
    void (GLAPIENTRY *ColorPointer)(GLint, GLenum, GLsizei, const GLvoid *);
    void (GLAPIENTRY *DeleteFramebuffers)(GLsizei, const GLuint *);
    void (GLAPIENTRY *DeleteRenderbuffers)(GLsizei, const GLuint *);
    void (GLAPIENTRY *Disable)(GLenum);
    void (GLAPIENTRY *DrawArrays)(GLenum, GLint, GLsizei);
    void (GLAPIENTRY *Enable)(GLenum);
    void (GLAPIENTRY *EnableClientState)(GLenum);
    void (GLAPIENTRY *Finish)(void);
    void (GLAPIENTRY *FramebufferRenderbuffer)(GLenum, GLenum, GLenum, GLuint);
    void (GLAPIENTRY *GenFramebuffers)(GLsizei, GLuint *);
    void (GLAPIENTRY *GenRenderbuffers)(GLsizei, GLuint *);
    GLenum (GLAPIENTRY *GetError)(void);
    void (GLAPIENTRY *GetIntegerv)(GLenum, GLint *);
    const GLubyte *(GLAPIENTRY *GetString)(GLenum);
    void (GLAPIENTRY *LoadIdentity)(void);
    void (GLAPIENTRY *MatrixMode)(GLenum);
    void (GLAPIENTRY *Ortho)(GLdouble, GLdouble, GLdouble, GLdouble, GLdouble, GLdouble);
    void (GLAPIENTRY *PixelStorei)(GLenum, GLint);
    void (GLAPIENTRY *ReadPixels)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, GLvoid *);
    void (GLAPIENTRY *RenderbufferStorage)(GLenum, GLenum, GLsizei, GLsizei);
    void (GLAPIENTRY *RenderbufferStorageMultisample)(GLenum, GLsizei, GLenum, GLsizei, GLsizei);
    void (GLAPIENTRY *Scissor)(GLint, GLint, GLsizei, GLsizei);
    void (GLAPIENTRY *VertexPointer)(GLint, GLenum, GLsizei, const GLvoid *);
    void (GLAPIENTRY *Viewport)(GLint, GLint, GLsizei, GLsizei);
} rjr_osm_api;

#define RJR_SYM(name, field) { name, offsetof(rjr_osm_api, field) }
static const struct { const char *name; size_t off; } rjr_osm_syms[] = {
    RJR_SYM("OSMesaCreateContextExt", CreateContextExt), RJR_SYM("OSMesaMakeCurrent", MakeCurrent),
    RJR_SYM("OSMesaGetCurrentContext", GetCurrentContext), RJR_SYM("OSMesaDestroyContext", DestroyContext),
    RJR_SYM("glBindFramebuffer", BindFramebuffer), RJR_SYM("glBindRenderbuffer", BindRenderbuffer),
    RJR_SYM("glBlitFramebuffer", BlitFramebuffer), RJR_SYM("glCheckFramebufferStatus", CheckFramebufferStatus),
    RJR_SYM("glClear", Clear), RJR_SYM("glClearColor", ClearColor), RJR_SYM("glColorPointer", ColorPointer),
    RJR_SYM("glDeleteFramebuffers", DeleteFramebuffers), RJR_SYM("glDeleteRenderbuffers", DeleteRenderbuffers),
    RJR_SYM("glDisable", Disable), RJR_SYM("glDrawArrays", DrawArrays), RJR_SYM("glEnable", Enable),
    RJR_SYM("glEnableClientState", EnableClientState), RJR_SYM("glFinish", Finish),
    RJR_SYM("glFramebufferRenderbuffer", FramebufferRenderbuffer), RJR_SYM("glGenFramebuffers", GenFramebuffers),
    RJR_SYM("glGenRenderbuffers", GenRenderbuffers), RJR_SYM("glGetError", GetError),
    RJR_SYM("glGetIntegerv", GetIntegerv), RJR_SYM("glGetString", GetString), RJR_SYM("glLoadIdentity", LoadIdentity),
    RJR_SYM("glMatrixMode", MatrixMode), RJR_SYM("glOrtho", Ortho), RJR_SYM("glPixelStorei", PixelStorei),
    RJR_SYM("glReadPixels", ReadPixels), RJR_SYM("glRenderbufferStorage", RenderbufferStorage),
    RJR_SYM("glRenderbufferStorageMultisample", RenderbufferStorageMultisample), RJR_SYM("glScissor", Scissor),
    RJR_SYM("glVertexPointer", VertexPointer), RJR_SYM("glViewport", Viewport)
};
#undef RJR_SYM
/* dlsym's void * goes into the function pointers by memcpy (POSIX: the same size) */
typedef char rjr_fnptr_is_pointer_size[sizeof(void *) == sizeof(void (*)(void)) ? 1 : -1];

static rjr_osm_api rjr_osm;                 /* written once by rjr_osm_load, then read only */
static int rjr_osm_status = -1;             /* 0 once every function is found */
static char rjr_osm_msg[400];               /* why not, otherwise */
static pthread_once_t rjr_osm_once = PTHREAD_ONCE_INIT;

static void rjr_osm_load(void)
{
    static const char *const names[] = { "libOSMesa.so.8", "libOSMesa.so" };
    const char *env = getenv("RJ_OSMESA"), *lib = names[0];
    const int from_env = env && env[0];
    char why[200];
    void *h = NULL, *p;
    OSMESAproc (GLAPIENTRY *gpa)(const char *) = NULL;
    size_t i;
    why[0] = 0;
    if (from_env) {
        lib = env;
        h = dlopen(lib, RTLD_NOW | RTLD_LOCAL);
        if (!h) snprintf(why, sizeof why, "%s", dlerror());
    } else {
        for (i = 0; !h && i < sizeof names / sizeof names[0]; i++) {
            h = dlopen(names[i], RTLD_NOW | RTLD_LOCAL);
            if (h) lib = names[i];
            else if (i == 0) snprintf(why, sizeof why, "%s", dlerror());
        }
    }
    if (!h) {
        snprintf(rjr_osm_msg, sizeof rjr_osm_msg,
                 "cannot load the OSMesa library %.100s%s, which draws the images (%.120s); "
                 "install it: apt-get install libosmesa6",
                 lib, from_env ? " (RJ_OSMESA)" : "", why);
        return;
    }
    p = dlsym(h, "OSMesaGetProcAddress");
    if (p) memcpy(&gpa, &p, sizeof p);
    for (i = 0; i < sizeof rjr_osm_syms / sizeof rjr_osm_syms[0]; i++) {
        char *dst = (char *)&rjr_osm + rjr_osm_syms[i].off;
        OSMESAproc f = NULL;
        p = dlsym(h, rjr_osm_syms[i].name);
        if (p) memcpy(dst, &p, sizeof p);
        else if (gpa && rjr_osm_syms[i].name[0] == 'g' && (f = gpa(rjr_osm_syms[i].name)) != NULL)
            memcpy(dst, &f, sizeof f);
        else {
            snprintf(rjr_osm_msg, sizeof rjr_osm_msg,
                     "the OSMesa library %.100s%s has no %s: not a usable OSMesa; "
                     "install it: apt-get install libosmesa6",
                     lib, from_env ? " (RJ_OSMESA)" : "", rjr_osm_syms[i].name);
            return;                         /* h stays open: harmless, never used */
        }
    }
    rjr_osm_status = 0;
}

int rjr_available(char *err, size_t errlen)
{
    set_err(err, errlen, "");
    if (pthread_once(&rjr_osm_once, rjr_osm_load) != 0) {
        set_err(err, errlen, "cannot load the OSMesa library: pthread_once failed");
        return -1;
    }
    if (rjr_osm_status != 0) set_err(err, errlen, rjr_osm_msg);
    return rjr_osm_status;
}

/* From here on the GL calls go through the table. */
#define glBindFramebuffer rjr_osm.BindFramebuffer
#define glBindRenderbuffer rjr_osm.BindRenderbuffer
#define glBlitFramebuffer rjr_osm.BlitFramebuffer
#define glCheckFramebufferStatus rjr_osm.CheckFramebufferStatus
#define glClear rjr_osm.Clear
#define glClearColor rjr_osm.ClearColor
#define glColorPointer rjr_osm.ColorPointer
#define glDeleteFramebuffers rjr_osm.DeleteFramebuffers
#define glDeleteRenderbuffers rjr_osm.DeleteRenderbuffers
#define glDisable rjr_osm.Disable
#define glDrawArrays rjr_osm.DrawArrays
#define glEnable rjr_osm.Enable
#define glEnableClientState rjr_osm.EnableClientState
#define glFinish rjr_osm.Finish
#define glFramebufferRenderbuffer rjr_osm.FramebufferRenderbuffer
#define glGenFramebuffers rjr_osm.GenFramebuffers
#define glGenRenderbuffers rjr_osm.GenRenderbuffers
#define glGetError rjr_osm.GetError
#define glGetIntegerv rjr_osm.GetIntegerv
#define glGetString rjr_osm.GetString
#define glLoadIdentity rjr_osm.LoadIdentity
#define glMatrixMode rjr_osm.MatrixMode
#define glOrtho rjr_osm.Ortho
#define glPixelStorei rjr_osm.PixelStorei
#define glReadPixels rjr_osm.ReadPixels
#define glRenderbufferStorage rjr_osm.RenderbufferStorage
#define glRenderbufferStorageMultisample rjr_osm.RenderbufferStorageMultisample
#define glScissor rjr_osm.Scissor
#define glVertexPointer rjr_osm.VertexPointer
#define glViewport rjr_osm.Viewport
#define OSMesaCreateContextExt rjr_osm.CreateContextExt
#define OSMesaMakeCurrent rjr_osm.MakeCurrent
#define OSMesaGetCurrentContext rjr_osm.GetCurrentContext
#define OSMesaDestroyContext rjr_osm.DestroyContext

static int be_bind(rjr_context *c)
{
    return OSMesaMakeCurrent(c->osm, c->osm_buf, GL_UNSIGNED_BYTE, c->width, c->height) ? 0 : -1;
}
static int be_create(rjr_context *c, char *err, size_t errlen)
{
    if (rjr_available(err, errlen) != 0) return -1;
    c->osm = OSMesaCreateContextExt(OSMESA_RGBA, 0, 0, 0, NULL);
    if (!c->osm) { set_err(err, errlen, "OSMesaCreateContextExt failed"); return -1; }
    c->osm_buf = (unsigned char *)malloc((size_t)c->width * (size_t)c->height * 4);
    if (!c->osm_buf) { OSMesaDestroyContext(c->osm); set_err(err, errlen, "out of memory"); return -1; }
    if (be_bind(c) != 0) {
        OSMesaDestroyContext(c->osm);
        free(c->osm_buf);
        set_err(err, errlen, "OSMesaMakeCurrent failed");
        return -1;
    }
    return 0;
}
static int be_make_current(rjr_context *c)
{
    if (OSMesaGetCurrentContext() == c->osm) return 0;
    return be_bind(c);
}
static int be_resize(rjr_context *c)
{
    unsigned char *nb = (unsigned char *)realloc(c->osm_buf, (size_t)c->width * (size_t)c->height * 4);
    if (!nb) return -1;
    c->osm_buf = nb;
    return be_bind(c);
}
static void be_destroy(rjr_context *c)
{
    OSMesaDestroyContext(c->osm);
    free(c->osm_buf);
}
static const char *be_name(void) { return "osmesa"; }
#endif

/* ---- Context -------------------------------------------------------------------------- */

static int fbo_attach(GLuint fbo, GLuint rb, int samples, int w, int h)
{
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 1) glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
    else glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE ? 0 : -1;
}

static int fbo_setup(rjr_context *c, char *err, size_t errlen)
{
    GLint maxs = 1;
    unsigned char *rb;
    if (!c->fbo_rs) {
        glGenFramebuffers(1, &c->fbo_rs);
        glGenRenderbuffers(1, &c->rb_rs);
        glGenFramebuffers(1, &c->fbo_ms);
        glGenRenderbuffers(1, &c->rb_ms);
    }
    if (fbo_attach(c->fbo_rs, c->rb_rs, 1, c->width, c->height) != 0) {
        set_err(err, errlen, "framebuffer object incomplete");
        return -1;
    }
    glGetIntegerv(GL_MAX_SAMPLES, &maxs);
    c->samples = maxs >= 4 ? 4 : (maxs >= 2 ? (int)maxs : 1);
    if (c->samples > 1 && fbo_attach(c->fbo_ms, c->rb_ms, c->samples, c->width, c->height) != 0)
        c->samples = 1;
    rb = (unsigned char *)realloc(c->readbuf, (size_t)c->width * (size_t)c->height * 4);
    if (!rb) { set_err(err, errlen, "out of memory"); return -1; }
    c->readbuf = rb;
    while (glGetError() != GL_NO_ERROR) {}
    return 0;
}

static void copy_gl_string(char *dst, size_t n, GLenum name)
{
    const GLubyte *s = glGetString(name);
    set_err(dst, n, s ? (const char *)s : "(unknown)");
}

rjr_context *rjr_create(int width, int height, char *err, size_t errlen)
{
    rjr_context *c;
    set_err(err, errlen, "");
    if (width < 1 || height < 1 || width > RJR_MAX_DIM || height > RJR_MAX_DIM) {
        set_err(err, errlen, "rjr_create: size out of range 1..16384");
        return NULL;
    }
    c = (rjr_context *)calloc(1, sizeof *c);
    if (!c) { set_err(err, errlen, "out of memory"); return NULL; }
    c->width = width;
    c->height = height;
    c->vxy = (float *)malloc(RJR_BATCH * 2 * sizeof(float));
    c->vcol = (unsigned char *)malloc(RJR_BATCH * 4);
    if (!c->vxy || !c->vcol || grow(&c->pa, &c->capa, 1024) || grow(&c->pb, &c->capb, 1024) ||
        grow(&c->pc, &c->capc, 1024)) {
        set_err(err, errlen, "out of memory");
        free(c->vxy); free(c->vcol); free(c->pa); free(c->pb); free(c->pc); free(c);
        return NULL;
    }
    if (be_create(c, err, errlen) != 0) {
        free(c->vxy); free(c->vcol); free(c->pa); free(c->pb); free(c->pc); free(c);
        return NULL;
    }
    copy_gl_string(c->renderer, sizeof c->renderer, GL_RENDERER);
    copy_gl_string(c->version, sizeof c->version, GL_VERSION);
    if (fbo_setup(c, err, errlen) != 0) {
        rjr_destroy(c);
        return NULL;
    }
    return c;
}

void rjr_destroy(rjr_context *c)
{
    if (!c) return;
    if (be_make_current(c) == 0 && c->fbo_rs) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &c->fbo_rs);
        glDeleteFramebuffers(1, &c->fbo_ms);
        glDeleteRenderbuffers(1, &c->rb_rs);
        glDeleteRenderbuffers(1, &c->rb_ms);
    }
    be_destroy(c);
    free(c->vxy); free(c->vcol); free(c->pa); free(c->pb); free(c->pc); free(c->readbuf);
    free(c->po);
    free(c->pl);
    free(c);
}

int rjr_resize(rjr_context *c, int width, int height)
{
    char e[200];
    if (width < 1 || height < 1 || width > RJR_MAX_DIM || height > RJR_MAX_DIM) {
        set_err(c->err, sizeof c->err, "rjr_resize: size out of range 1..16384");
        return -1;
    }
    if (c->in_frame) { set_err(c->err, sizeof c->err, "rjr_resize: inside a frame"); return -1; }
    if (width == c->width && height == c->height) return 0;
    c->width = width;
    c->height = height;
    c->has_frame = 0;
    if (be_resize(c) != 0) { set_err(c->err, sizeof c->err, "rjr_resize: make current failed"); return -1; }
    if (fbo_setup(c, e, sizeof e) != 0) { set_err(c->err, sizeof c->err, e); return -1; }
    return 0;
}

int rjr_width(const rjr_context *c) { return c->width; }
int rjr_height(const rjr_context *c) { return c->height; }
int rjr_samples(const rjr_context *c) { return c->samples; }
const char *rjr_gl_renderer(const rjr_context *c) { return c->renderer; }
const char *rjr_gl_version(const rjr_context *c) { return c->version; }
const char *rjr_backend(const rjr_context *c) { (void)c; return be_name(); }
const char *rjr_error(const rjr_context *c) { return c->err; }

/* ---- Frames and the triangle batch ------------------------------------------------------ */

static void flush(rjr_context *c)
{
    if (c->nv == 0) return;
    glVertexPointer(2, GL_FLOAT, 0, c->vxy);
    glColorPointer(4, GL_UNSIGNED_BYTE, 0, c->vcol);
    glDrawArrays(GL_TRIANGLES, 0, c->nv);
    c->nv = 0;
}

static void tri(rjr_context *c, double ax, double ay, double bx, double by, double cx, double cy, rjr_rgb col)
{
    float *v;
    unsigned char *k;
    int i;
    if (!c->in_frame) { ctx_fail(c, "drawing outside rjr_begin/rjr_end"); return; }
    if (c->nv + 3 > RJR_BATCH) flush(c);
    v = c->vxy + 2 * c->nv;
    k = c->vcol + 4 * c->nv;
    v[0] = (float)ax; v[1] = (float)ay; v[2] = (float)bx; v[3] = (float)by; v[4] = (float)cx; v[5] = (float)cy;
    for (i = 0; i < 3; i++) {
        k[4 * i + 0] = (unsigned char)((col >> 16) & 255);
        k[4 * i + 1] = (unsigned char)((col >> 8) & 255);
        k[4 * i + 2] = (unsigned char)(col & 255);
        k[4 * i + 3] = 255;
    }
    c->nv += 3;
}

static void quad(rjr_context *c, double ax, double ay, double bx, double by, double cx, double cy,
                 double dx, double dy, rjr_rgb col)
{
    tri(c, ax, ay, bx, by, cx, cy, col);
    tri(c, ax, ay, cx, cy, dx, dy, col);
}

int rjr_begin(rjr_context *c, rjr_rgb bg)
{
    if (c->in_frame) { set_err(c->err, sizeof c->err, "rjr_begin: frame already open"); return -1; }
    if (be_make_current(c) != 0) { set_err(c->err, sizeof c->err, "rjr_begin: make current failed"); return -1; }
    c->failed = 0;
    c->err[0] = 0;
    c->nv = 0;
    glBindFramebuffer(GL_FRAMEBUFFER, c->samples > 1 ? c->fbo_ms : c->fbo_rs);
    glViewport(0, 0, c->width, c->height);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_LIGHTING);
    glDisable(GL_TEXTURE_2D);
    glDisable(GL_DITHER);
    if (c->samples > 1) glEnable(GL_MULTISAMPLE);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0.0, (double)c->width, (double)c->height, 0.0, -1.0, 1.0);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    glClearColor((float)((bg >> 16) & 255) / 255.0f, (float)((bg >> 8) & 255) / 255.0f,
                 (float)(bg & 255) / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    c->in_frame = 1;
    return 0;
}

int rjr_end(rjr_context *c)
{
    GLenum e;
    if (!c->in_frame) { set_err(c->err, sizeof c->err, "rjr_end: no open frame"); return -1; }
    flush(c);
    glDisable(GL_SCISSOR_TEST);
    if (c->samples > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, c->fbo_ms);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, c->fbo_rs);
        glBlitFramebuffer(0, 0, c->width, c->height, 0, 0, c->width, c->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glFinish();
    c->in_frame = 0;
    e = glGetError();
    if (e != GL_NO_ERROR) {
        char m[64];
        snprintf(m, sizeof m, "OpenGL error 0x%04x", (unsigned)e);
        ctx_fail(c, m);
        while (glGetError() != GL_NO_ERROR) {}
    }
    c->has_frame = !c->failed;
    return c->failed ? -1 : 0;
}

void rjr_clip(rjr_context *c, int x, int y, int w, int h)
{
    if (!c->in_frame) return;
    flush(c);
    if (w <= 0 || h <= 0) {
        glDisable(GL_SCISSOR_TEST);
        return;
    }
    glEnable(GL_SCISSOR_TEST);
    glScissor(x, c->height - (y + h), w, h);
}

int rjr_read_pixels(rjr_context *c, unsigned char *rgb)
{
    int y, x, w = c->width, h = c->height;
    if (!c->has_frame) { set_err(c->err, sizeof c->err, "rjr_read_pixels: no finished frame"); return -1; }
    if (be_make_current(c) != 0) { set_err(c->err, sizeof c->err, "rjr_read_pixels: make current failed"); return -1; }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, c->fbo_rs);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, c->readbuf);
    if (glGetError() != GL_NO_ERROR) { set_err(c->err, sizeof c->err, "glReadPixels failed"); return -1; }
    for (y = 0; y < h; y++) {                     /* GL rows are bottom-up */
        const unsigned char *s = c->readbuf + (size_t)(h - 1 - y) * (size_t)w * 4;
        unsigned char *d = rgb + (size_t)y * (size_t)w * 3;
        for (x = 0; x < w; x++) {
            d[0] = s[0]; d[1] = s[1]; d[2] = s[2];
            d += 3; s += 4;
        }
    }
    return 0;
}

/* ---- Geometry primitives ------------------------------------------------------------------ */

static int disc_segments(double r)
{
    double step;
    int n;
    if (r <= 1.0) return 8;
    step = 2.0 * acos(1.0 - 0.1 / r);            /* chord error 0.1 px */
    n = (int)ceil(2.0 * M_PI / step);
    return n < 8 ? 8 : (n > 96 ? 96 : n);
}

void rjr_disc(rjr_context *c, double x, double y, double r, rjr_rgb col)
{
    int i, n = disc_segments(r);
    double px = x + r, py = y;
    if (!(r > 0)) return;
    for (i = 1; i <= n; i++) {
        double a = 2.0 * M_PI * i / n;
        double qx = x + r * cos(a), qy = y + r * sin(a);
        tri(c, x, y, px, py, qx, qy, col);
        px = qx; py = qy;
    }
}

void rjr_rect(rjr_context *c, double x, double y, double w, double h, rjr_rgb col)
{
    if (w <= 0 || h <= 0) return;
    quad(c, x, y, x + w, y, x + w, y + h, x, y + h, col);
}

/* Outline of a rectangle with a line of width lw inside the edges. */
static void rect_outline(rjr_context *c, double x, double y, double w, double h, double lw, rjr_rgb col)
{
    rjr_rect(c, x, y, w, lw, col);
    rjr_rect(c, x, y + h - lw, w, lw, col);
    rjr_rect(c, x, y + lw, lw, h - 2 * lw, col);
    rjr_rect(c, x + w - lw, y + lw, lw, h - 2 * lw, col);
}

/* Fills the outer side of a join between directions (d0) and (d1) at P. */
static void join(rjr_context *c, double px, double py, double d0x, double d0y, double d1x, double d1y, double hw, rjr_rgb col)
{
    double cr = d0x * d1y - d0y * d1x, dt = d0x * d1x + d0y * d1y;
    double s, ax, ay, bx, by, ch;
    if (fabs(cr) < 1e-9 && dt > 0) return;
    s = cr > 0 ? -1.0 : 1.0;
    ax = -d0y * hw * s; ay = d0x * hw * s;
    bx = -d1y * hw * s; by = d1x * hw * s;
    ch = sqrt(0.5 * (1.0 + dt));                  /* cos of half the turn angle */
    if (ch > 0.5) {                               /* miter (turn < 120 degrees) */
        double mx = ax + bx, my = ay + by, ml = sqrt(mx * mx + my * my);
        double len = hw / ch;
        mx = mx / ml * len; my = my / ml * len;
        tri(c, px, py, px + ax, py + ay, px + mx, py + my, col);
        tri(c, px, py, px + mx, py + my, px + bx, py + by, col);
    } else {                                      /* round join */
        double a0 = atan2(ay, ax);
        double sw = atan2(ax * by - ay * bx, ax * bx + ay * by);
        int i, n = (int)ceil(fabs(sw) / (2.0 * M_PI) * disc_segments(hw));
        double qx = px + ax, qy = py + ay;
        if (n < 1) n = 1;
        for (i = 1; i <= n; i++) {
            double a = a0 + sw * i / n;
            double rx = px + hw * cos(a), ry = py + hw * sin(a);
            tri(c, px, py, qx, qy, rx, ry, col);
            qx = rx; qy = ry;
        }
    }
}

/* Thick polyline through n points p[2n] (pixels). caps: 0 butt, 1 round, 2 square (extend
   by half the width). Joins are mitred, round when the turn exceeds 120 degrees. */
static void stroke(rjr_context *c, const double *p, int n, double width, rjr_rgb col, int caps)
{
    double hw = 0.5 * width, *q, pdx = 0, pdy = 0;
    int i, m = 0;
    if (n < 1 || !(width > 0)) return;
    if (grow(&c->pc, &c->capc, (size_t)n)) { ctx_fail(c, "out of memory"); return; }
    q = c->pc;
    for (i = 0; i < n; i++) {
        if (!isfinite(p[2 * i]) || !isfinite(p[2 * i + 1])) continue;
        if (m > 0 && fabs(p[2 * i] - q[2 * m - 2]) < 1e-4 && fabs(p[2 * i + 1] - q[2 * m - 1]) < 1e-4) continue;
        q[2 * m] = p[2 * i];
        q[2 * m + 1] = p[2 * i + 1];
        m++;
    }
    if (m == 0) return;
    if (m == 1) {
        if (caps == 1) rjr_disc(c, q[0], q[1], hw, col);
        else if (caps == 2) rjr_rect(c, q[0] - hw, q[1] - hw, width, width, col);
        return;
    }
    for (i = 0; i + 1 < m; i++) {
        double ax = q[2 * i], ay = q[2 * i + 1], bx = q[2 * i + 2], by = q[2 * i + 3];
        double dx = bx - ax, dy = by - ay, l = sqrt(dx * dx + dy * dy), nx, ny;
        dx /= l; dy /= l;
        nx = -dy * hw; ny = dx * hw;
        if (caps == 2 && i == 0) { ax -= dx * hw; ay -= dy * hw; }
        if (caps == 2 && i + 2 == m) { bx += dx * hw; by += dy * hw; }
        quad(c, ax + nx, ay + ny, ax - nx, ay - ny, bx - nx, by - ny, bx + nx, by + ny, col);
        if (i > 0) join(c, q[2 * i], q[2 * i + 1], pdx, pdy, dx, dy, hw, col);
        pdx = dx; pdy = dy;
    }
    if (caps == 1) {
        rjr_disc(c, q[0], q[1], hw, col);
        rjr_disc(c, q[2 * m - 2], q[2 * m - 1], hw, col);
    }
}

/* Dashed polyline: dashes of length on, gaps off (pixels), butt caps. */
static void stroke_dashed(rjr_context *c, const double *p, int n, double width, rjr_rgb col, double on, double off)
{
    double pos = 0.0;        /* distance into the current dash or gap */
    int i, k, drawing = 1;
    if (n < 2) return;
    if (grow(&c->pb, &c->capb, (size_t)n + 2)) { ctx_fail(c, "out of memory"); return; }
    c->pb[0] = p[0]; c->pb[1] = p[1]; k = 1;
    for (i = 0; i + 1 < n; i++) {
        double ax = p[2 * i], ay = p[2 * i + 1], bx = p[2 * i + 2], by = p[2 * i + 3];
        double l = sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay)), t = 0.0;
        if (!isfinite(l)) continue;
        while (t < l) {
            double remain = (drawing ? on : off) - pos;
            if (t + remain <= l) {                /* the dash or gap ends in this segment */
                double x, y;
                t += remain;
                x = ax + (bx - ax) * (t / l);
                y = ay + (by - ay) * (t / l);
                if (drawing) {
                    c->pb[2 * k] = x; c->pb[2 * k + 1] = y; k++;
                    stroke(c, c->pb, k, width, col, 0);
                    k = 0;
                } else {
                    c->pb[0] = x; c->pb[1] = y; k = 1;
                }
                drawing = !drawing;
                pos = 0.0;
            } else {
                pos += l - t;
                t = l;
                if (drawing) { c->pb[2 * k] = bx; c->pb[2 * k + 1] = by; k++; }
            }
        }
    }
    if (drawing && k > 1) stroke(c, c->pb, k, width, col, 0);
}

void rjr_line(rjr_context *c, double x0, double y0, double x1, double y1, double width, rjr_rgb col)
{
    double p[4];
    p[0] = x0; p[1] = y0; p[2] = x1; p[3] = y1;
    stroke(c, p, 2, width, col, 1);
}

void rjr_polyline(rjr_context *c, const double *xy, int n, double width, rjr_rgb col, int dashed)
{
    if (dashed) stroke_dashed(c, xy, n, width, col, width * 4 + 2, width * 2.5 + 2);
    else stroke(c, xy, n, width, col, 1);
}

/* ---- Stroke font ------------------------------------------------------------------------
   Glyph coordinates: y up, baseline 0, capitals 12 high, x-height 8, descenders to -4.
   Path language: "M x y" starts a stroke, "L x y" adds a point, "A cx cy rx ry a0 a1" adds
   an elliptic arc from angle a0 to a1 (degrees, counter-clockwise positive; joined to the
   current stroke if there is one), "|" ends the stroke. Strokes have round caps and joins. */

typedef struct glyph { char ch; float w; const char *path; } glyph;

static const glyph font_glyphs[] = {
    { ' ', 4.0f, "" },
    { '0', 7.0f, "A3.5 6 3.5 6 0 360" },
    { '1', 7.0f, "M1.2 9.6 L4 12 L4 0|M1.2 0 L6.8 0" },
    { '2', 7.0f, "A3.5 8.5 3.4 3.5 160 -35 L0 0 L7 0" },
    { '3', 7.0f, "A3.5 9.25 3.2 2.75 160 -90 A3.5 3.25 3.5 3.25 90 -160" },
    { '4', 7.0f, "M5.2 0 L5.2 12 L0 3.6 L7 3.6" },
    { '5', 7.0f, "M6.6 12 L1 12 L0.6 6.6 A3.4 4 3.6 4 140 -150" },
    { '6', 7.0f, "A3.5 3.8 3.5 3.8 0 360|M0 3.8 A6.5 3.8 6.5 8.2 180 100" },
    { '7', 7.0f, "M0 12 L7 12 L2.4 0" },
    { '8', 7.0f, "A3.5 9.1 3.0 2.9 -90 270|A3.5 3.1 3.5 3.1 90 450" },
    { '9', 7.0f, "A3.5 8.2 3.5 3.8 0 360|M7 8.2 A0.5 8.2 6.5 8.2 0 -80" },
    { 'A', 8.0f, "M0 0 L4 12 L8 0|M1.4 4.2 L6.6 4.2" },
    { 'B', 7.2f, "M0 6.4 L4 6.4|M0 0 L0 12 L3.8 12 A3.8 9.2 2.9 2.8 90 -90 L0 6.4|M4 6.4 A4 3.2 3.2 3.2 90 -90 L0 0" },
    { 'C', 8.0f, "A4.3 6 4.3 6 45 315" },
    { 'D', 8.0f, "M0 0 L0 12 L2.8 12 A2.8 6 5.2 6 90 -90 L0 0" },
    { 'E', 7.0f, "M7 12 L0 12 L0 0 L7 0|M0 6.2 L5.6 6.2" },
    { 'F', 7.0f, "M7 12 L0 12 L0 0|M0 6.2 L5.6 6.2" },
    { 'G', 8.4f, "A4.3 6 4.3 6 45 360 L8.6 5.4 L5 5.4" },
    { 'H', 7.6f, "M0 0 L0 12|M7.6 0 L7.6 12|M0 6.2 L7.6 6.2" },
    { 'I', 3.0f, "M1.5 0 L1.5 12|M0 12 L3 12|M0 0 L3 0" },
    { 'J', 6.0f, "M6 12 L6 3 A3 3 3 3 0 -170" },
    { 'K', 7.4f, "M0 0 L0 12|M7.4 12 L0 4|M2.8 7 L7.4 0" },
    { 'L', 6.6f, "M0 12 L0 0 L6.6 0" },
    { 'M', 9.0f, "M0 0 L0 12 L4.5 3 L9 12 L9 0" },
    { 'N', 7.6f, "M0 0 L0 12 L7.6 0 L7.6 12" },
    { 'O', 9.0f, "A4.5 6 4.5 6 0 360" },
    { 'P', 7.0f, "M0 0 L0 12 L3.8 12 A3.8 9 3.2 3 90 -90 L0 6" },
    { 'Q', 9.0f, "A4.5 6 4.5 6 0 360|M5.6 3 L9 -0.6" },
    { 'R', 7.4f, "M0 0 L0 12 L3.8 12 A3.8 9 3.2 3 90 -90 L0 6|M3.8 6 L7.4 0" },
    { 'S', 7.0f, "A3.6 9 3.2 3 20 270 A3.5 3 3.5 3 90 -160" },
    { 'T', 8.0f, "M0 12 L8 12|M4 12 L4 0" },
    { 'U', 7.6f, "M0 12 L0 4 A3.8 4 3.8 4 180 360 L7.6 12" },
    { 'V', 8.0f, "M0 12 L4 0 L8 12" },
    { 'W', 11.0f, "M0 12 L2.75 0 L5.5 9 L8.25 0 L11 12" },
    { 'X', 8.0f, "M0 12 L8 0|M0 0 L8 12" },
    { 'Y', 8.0f, "M0 12 L4 6 L8 12|M4 6 L4 0" },
    { 'Z', 7.6f, "M0 12 L7.6 12 L0 0 L7.6 0" },
    { 'a', 6.4f, "A3.2 4 3.2 4 0 360|M6.4 8 L6.4 0" },
    { 'b', 6.4f, "M0 12 L0 0|A3.2 4 3.2 4 0 360" },
    { 'c', 6.2f, "A3.4 4 3.4 4 45 315" },
    { 'd', 6.4f, "A3.2 4 3.2 4 0 360|M6.4 12 L6.4 0" },
    { 'e', 6.6f, "M0.1 4 L6.6 4 A3.35 4 3.25 4 0 320" },
    { 'f', 5.0f, "A3.8 9.6 2 2.4 30 180 L1.8 0|M0 8 L4.6 8" },
    { 'g', 6.4f, "A3.2 4 3.2 4 0 360|M6.4 8 L6.4 -1 A3.2 -1 3.2 3 0 -165" },
    { 'h', 6.4f, "M0 12 L0 0|M0 5 A3.2 5 3.2 3 180 0 L6.4 0" },
    { 'i', 1.0f, "M0.5 0 L0.5 8|M0.5 10.6 L0.5 11" },
    { 'j', 3.0f, "M2.5 8 L2.5 -1.5 A0 -1.5 2.5 2.5 0 -120|M2.5 10.6 L2.5 11" },
    { 'k', 6.0f, "M0 12 L0 0|M6 8 L0 2.6|M2.2 4.6 L6 0" },
    { 'l', 1.0f, "M0.5 12 L0.5 0" },
    { 'm', 10.0f, "M0 8 L0 0|M0 5 A2.5 5 2.5 3 180 0 L5 0|M5 5 A7.5 5 2.5 3 180 0 L10 0" },
    { 'n', 6.4f, "M0 8 L0 0|M0 5 A3.2 5 3.2 3 180 0 L6.4 0" },
    { 'o', 6.8f, "A3.4 4 3.4 4 0 360" },
    { 'p', 6.4f, "M0 8 L0 -4|A3.2 4 3.2 4 0 360" },
    { 'q', 6.4f, "A3.2 4 3.2 4 0 360|M6.4 8 L6.4 -4" },
    { 'r', 4.8f, "M0 8 L0 0|M0 4.4 A4 4.4 4 3.6 180 80" },
    { 's', 6.0f, "A3.1 6 2.8 2 25 270 A3 2 3 2 90 -155" },
    { 't', 4.6f, "M1.5 11 L1.5 1.6 A3.1 1.6 1.6 1.6 180 300|M0 8 L4.4 8" },
    { 'u', 6.4f, "M0 8 L0 3 A3.2 3 3.2 3 180 360|M6.4 8 L6.4 0" },
    { 'v', 6.4f, "M0 8 L3.2 0 L6.4 8" },
    { 'w', 9.0f, "M0 8 L2.25 0 L4.5 6 L6.75 0 L9 8" },
    { 'x', 6.0f, "M0 8 L6 0|M0 0 L6 8" },
    { 'y', 6.4f, "M0 8 L3.3 0|M6.4 8 L2.2 -2.8 A0.8 -3.3 1.4 0.9 -20 -120" },
    { 'z', 6.0f, "M0 8 L6 8 L0 0 L6 0" },
    { '.', 1.0f, "M0.5 0.2 L0.5 0.6" },
    { ',', 1.5f, "M1 0.6 L1 0 L0 -2.2" },
    { '-', 5.0f, "M0.5 4.6 L4.5 4.6" },
    { '+', 7.0f, "M0 5 L7 5|M3.5 1.5 L3.5 8.5" },
    { '=', 7.0f, "M0 3.4 L7 3.4|M0 6.6 L7 6.6" },
    { '(', 3.0f, "A6 4.5 6 8.6 122 238" },
    { ')', 3.0f, "A-3 4.5 6 8.6 58 -58" },
    { '[', 3.0f, "M3 12.5 L0.3 12.5 L0.3 -3 L3 -3" },
    { ']', 3.0f, "M0 12.5 L2.7 12.5 L2.7 -3 L0 -3" },
    { '/', 5.0f, "M0 -2 L5 12.5" },
    { ':', 1.0f, "M0.5 0.2 L0.5 0.6|M0.5 6.4 L0.5 6.8" },
    { '%', 9.0f, "M0.4 0 L8.6 12|A2 9.6 2 2.4 0 360|A7 2.4 2 2.4 0 360" },
    { '_', 7.0f, "M0 -2 L7 -2" },
    { '\'', 1.0f, "M0.5 12 L0.5 9" },
    { '*', 6.0f, "M3 12 L3 6|M0.4 10.5 L5.6 7.5|M0.4 7.5 L5.6 10.5" },
    { '<', 6.0f, "M6 9.5 L0 5 L6 0.5" },
    { '>', 6.0f, "M0 9.5 L6 5 L0 0.5" },
    { '!', 1.0f, "M0.5 12 L0.5 3.5|M0.5 0.2 L0.5 0.6" },
    { '?', 6.0f, "A3 9 3 3 160 -60 A4.5 5 2 2 120 180 L2.5 3.5|M2.5 0.2 L2.5 0.6" },
    { '#', 8.0f, "M2.5 0 L3.5 12|M5 0 L6 12|M0.5 4 L8 4|M0.5 8 L8 8" },
};

#define FONT_CAP 12.0
#define FONT_DESC 4.0
#define FONT_GAP 3.0
static const glyph font_unknown = { '?', 6.0f, "M0 0 L6 0 L6 12 L0 12 L0 0" };

static const glyph *font_find(int ch)
{
    size_t i;
    for (i = 0; i < sizeof font_glyphs / sizeof font_glyphs[0]; i++)
        if (font_glyphs[i].ch == ch) return &font_glyphs[i];
    return &font_unknown;
}

static const char *parse_num(const char *p, double *v)
{
    double sign = 1.0, x = 0.0, f = 0.1;
    while (*p == ' ' || *p == ',') p++;
    if (*p == '-') { sign = -1.0; p++; }
    while (*p >= '0' && *p <= '9') x = x * 10.0 + (*p++ - '0');
    if (*p == '.') {
        p++;
        while (*p >= '0' && *p <= '9') { x += f * (*p++ - '0'); f *= 0.1; }
    }
    *v = sign * x;
    return p;
}

double rjr_text_width(const char *s, double size_px)
{
    double w = 0.0;
    int n = 0;
    if (!s) return 0.0;
    for (; *s; s++, n++) w += font_find((unsigned char)*s)->w + FONT_GAP;
    if (n > 0) w -= FONT_GAP;
    return w * size_px / FONT_CAP;
}

typedef struct text_xf { double ox, oy, dx, dy, ux, uy, sc; } text_xf;   /* origin, baseline dir, up dir, scale */

static void glyph_point(const text_xf *t, double pen, double u, double v, double *x, double *y)
{
    double a = (pen + u) * t->sc, b = v * t->sc;
    *x = t->ox + a * t->dx + b * t->ux;
    *y = t->oy + a * t->dy + b * t->uy;
}

static void draw_glyph(rjr_context *c, const glyph *g, const text_xf *t, double pen, double sw, rjr_rgb col)
{
    const char *p = g->path;
    int k = 0;
    while (*p) {
        char cmd = *p++;
        if (cmd == ' ') continue;
        if (cmd == '|' || cmd == 'M') {
            if (k > 0) stroke(c, c->pa, k, sw, col, 1);
            k = 0;
        }
        if (cmd == 'M' || cmd == 'L') {
            double u, v;
            p = parse_num(p, &u);
            p = parse_num(p, &v);
            if (grow(&c->pa, &c->capa, (size_t)k + 1)) { ctx_fail(c, "out of memory"); return; }
            glyph_point(t, pen, u, v, &c->pa[2 * k], &c->pa[2 * k + 1]);
            k++;
        } else if (cmd == 'A') {
            double cx, cy, rx, ry, a0, a1, rpx;
            int i, n;
            p = parse_num(p, &cx); p = parse_num(p, &cy); p = parse_num(p, &rx);
            p = parse_num(p, &ry); p = parse_num(p, &a0); p = parse_num(p, &a1);
            rpx = (rx > ry ? rx : ry) * t->sc;
            n = (int)ceil(fabs(a1 - a0) / 360.0 * (rpx * 3.0 < 16 ? 16 : (rpx * 3.0 > 72 ? 72 : rpx * 3.0)));
            if (n < 2) n = 2;
            if (grow(&c->pa, &c->capa, (size_t)k + (size_t)n + 1)) { ctx_fail(c, "out of memory"); return; }
            for (i = 0; i <= n; i++) {
                double a = (a0 + (a1 - a0) * i / n) * (M_PI / 180.0);
                glyph_point(t, pen, cx + rx * cos(a), cy + ry * sin(a), &c->pa[2 * k], &c->pa[2 * k + 1]);
                k++;
            }
        }
    }
    if (k > 0) stroke(c, c->pa, k, sw, col, 1);
}

double rjr_text(rjr_context *c, double x, double y, double size_px, double angle_deg, int align, rjr_rgb col, const char *s)
{
    text_xf t;
    double w, a = angle_deg * (M_PI / 180.0), hoff, voff, pen = 0.0;
    double sw = size_px * 0.095 < 1.0 ? 1.0 : size_px * 0.095;
    if (!s || !(size_px > 0)) return 0.0;
    w = rjr_text_width(s, size_px);
    t.sc = size_px / FONT_CAP;
    t.dx = cos(a); t.dy = -sin(a);          /* baseline direction on screen (y down) */
    t.ux = -sin(a); t.uy = -cos(a);         /* up direction */
    switch (align & 3) {
    case RJR_CENTER: hoff = -0.5 * w; break;
    case RJR_RIGHT: hoff = -w; break;
    default: hoff = 0.0; break;
    }
    switch (align & 12) {
    case RJR_TOP: voff = -size_px; break;
    case RJR_MIDDLE: voff = -0.5 * size_px; break;
    case RJR_BOTTOM: voff = FONT_DESC * t.sc; break;
    default: voff = 0.0; break;
    }
    t.ox = x + hoff * t.dx + voff * t.ux;
    t.oy = y + hoff * t.dy + voff * t.uy;
    for (; *s; s++) {
        const glyph *g = font_find((unsigned char)*s);
        draw_glyph(c, g, &t, pen, sw, col);
        pen += g->w + FONT_GAP;
    }
    return w;
}

#ifndef RJR_NO_SCENE
/* ---- Mechanism frames ------------------------------------------------------------------ */

static const rjr_rgb link_fill[] = { 0x8db3e2, 0x9fcf9a, 0xf2c27e, 0xc3a8e0, 0xe8a3a8, 0x8fd3d0 };
#define COL_GROUND   0x4d4d4du
#define COL_GROUNDF  0xd9d9d9u
#define COL_ARC      0x7d8ea6u
#define COL_STOP     0x3d3d3du
#define COL_FREE     0x1f5fbfu
#define COL_LIMIT    0xf08c00u
#define COL_LOCKED   0xd01f1fu

/* Arc of radius r around (x, y) from world angle a0 to a1 (radians, counter-clockwise on
   screen) as a stroke of the given width. */
static void arc_stroke(rjr_context *c, double x, double y, double r, double a0, double a1, double width, rjr_rgb col, int caps)
{
    int i, n = (int)ceil(fabs(a1 - a0) / (2.0 * M_PI) * disc_segments(r));
    if (n < 1) n = 1;
    if (grow(&c->pa, &c->capa, (size_t)n + 1)) { ctx_fail(c, "out of memory"); return; }
    for (i = 0; i <= n; i++) {
        double a = a0 + (a1 - a0) * i / n;
        c->pa[2 * i] = x + r * cos(a);
        c->pa[2 * i + 1] = y - r * sin(a);
    }
    stroke(c, c->pa, n + 1, width, col, caps);
}

static rjr_rgb darker(rjr_rgb c, double f)
{
    unsigned r = (unsigned)(((c >> 16) & 255) * f), g = (unsigned)(((c >> 8) & 255) * f), b = (unsigned)((c & 255) * f);
    return (rjr_rgb)((r << 16) | (g << 8) | b);
}

rjr_view rjr_view_default(void)
{
    rjr_view v;
    memset(&v, 0, sizeof v);
    v.mpp = 0.005;
    v.thickness_factor = 1.0;
    v.min_thickness_px = 3.0;
    v.show_time = 1;
    v.show_scale = 1;
    v.show_limits = 1;
    v.show_ground = 1;
    v.background = 0xffffff;
    return v;
}

void rjr_bbox_init(double box[4])
{
    box[0] = box[1] = HUGE_VAL;
    box[2] = box[3] = -HUGE_VAL;
}

static void bbox_pt(double box[4], const double p[2])
{
    if (!isfinite(p[0]) || !isfinite(p[1])) return;
    if (p[0] < box[0]) box[0] = p[0];
    if (p[1] < box[1]) box[1] = p[1];
    if (p[0] > box[2]) box[2] = p[0];
    if (p[1] > box[3]) box[3] = p[1];
}

void rjr_bbox_add(double box[4], const rj_model *m, const rj_state *s)
{
    int l, k, j, nl = rj_model_link_count(m), nj = rj_model_joint_count(m);
    double p[2];
    for (l = 0; l < nl; l++)
        for (k = 0; k < rj_link_node_count(m, l); k++) {
            rj_node_position(m, s, l, k, p);
            bbox_pt(box, p);
        }
    for (j = 0; j < nj; j++) {
        const rj_joint_def *jd = rj_model_joint_def(m, j);
        rj_joint_position(m, s, j, p);
        bbox_pt(box, p);
        if (jd->body1 < 0) {
            p[0] = jd->ground_x; p[1] = jd->ground_y;
            bbox_pt(box, p);
        }
    }
}

int rjr_view_fit_box(rjr_view *v, const double box[4], int width, int height, double margin_px)
{
    double bw, bh, aw, ah, mpp;
    if (!(box[2] >= box[0]) || !(box[3] >= box[1]) || width < 1 || height < 1) return -1;
    bw = box[2] - box[0];
    bh = box[3] - box[1];
    aw = width - 2.0 * margin_px;
    ah = height - 2.0 * margin_px;
    if (aw < 1.0) aw = 1.0;
    if (ah < 1.0) ah = 1.0;
    mpp = bw / aw > bh / ah ? bw / aw : bh / ah;
    if (!(mpp > 0)) mpp = v->mpp > 0 ? v->mpp : 0.005;
    v->mpp = mpp;
    v->cx = 0.5 * (box[0] + box[2]);
    v->cy = 0.5 * (box[1] + box[3]);
    return 0;
}

int rjr_view_fit(rjr_view *v, const rj_model *m, const rj_state *s, int width, int height, double margin_px)
{
    double box[4];
    rjr_bbox_init(box);
    rjr_bbox_add(box, m, s);
    return rjr_view_fit_box(v, box, width, height, margin_px);
}

typedef struct scene_xf { double cx, cy, mpp, hw, hh; } scene_xf;

static void w2p(const scene_xf *t, const double w[2], double *x, double *y)
{
    *x = t->hw + (w[0] - t->cx) / t->mpp;
    *y = t->hh - (w[1] - t->cy) / t->mpp;
}

/* The overlay font (capital height): the view's, else 2.8 % of the height within 11..18. */
static double view_font(const rjr_context *c, const rjr_view *v)
{
    double f = c->height * 0.028;
    if (v->font_px > 0)
        return v->font_px;
    if (f < 11)
        return 11;
    if (f > 18)
        return 18;
    return f;
}

/* Height of the text band: the texts' top margin, their capitals and descenders (4/3 of
   the capital height) and half the margin below them. 0 when the view does not ask for it
   or the image is too low (the scene keeps at least half the height). */
static double band_of(const rjr_context *c, const rjr_view *v, double f)
{
    double pad = floor(f * 0.8);
    double b = ceil(pad + f * 4.0 / 3.0 + 0.5 * pad);
    if (!v->text_band || b > 0.5 * c->height)
        return 0.0;
    return b;
}

/* World to pixel transform of a view. With a band the whole view is scaled by
   k = (height - band) / height about the top centre and moved below the band, the same for
   every frame, so an animation does not jump and no link can reach the texts. */
static void scene_transform(const rjr_context *c, const rjr_view *v, double band, scene_xf *t)
{
    double k = (c->height - band) / c->height;
    t->cx = v->cx;
    t->cy = v->cy;
    t->mpp = v->mpp;
    t->hw = 0.5 * c->width;
    t->hh = 0.5 * c->height;
    if (!(band > 0))
        return;
    t->mpp = v->mpp / k;
    t->hh = band + k * 0.5 * c->height;
}

void rjr_world_to_pixel(const rjr_context *c, const rjr_view *v, double x, double y, double *px, double *py)
{
    scene_xf t;
    double w[2];
    scene_transform(c, v, band_of(c, v, view_font(c, v)), &t);
    w[0] = x;
    w[1] = y;
    w2p(&t, w, px, py);
}

static double link_thickness_px(const rj_model *m, int l, const rjr_view *v)
{
    double h = rj_model_link_def(m, l)->height, t = h > 0 ? h * v->thickness_factor / v->mpp : 0.0;
    return t > v->min_thickness_px ? t : v->min_thickness_px;
}

/* Hatched ground line from (x0,y0) to (x1,y1); hatches go to the side (hx, hy) (unit). */
static void ground_line(rjr_context *c, double x0, double y0, double x1, double y1, double hx, double hy, double hl)
{
    double dx = x1 - x0, dy = y1 - y0, l = sqrt(dx * dx + dy * dy), sp = hl * 0.75;
    int i, n = (int)floor(l / sp);
    rjr_line(c, x0, y0, x1, y1, 2.0, COL_GROUND);
    for (i = 0; i <= n; i++) {
        double f = (l - n * sp) * 0.5 / l + (double)i * sp / l;
        double px = x0 + dx * f, py = y0 + dy * f;
        /* hatches slanted 45 degrees against the line direction */
        double ex = px + (hx - dx / l) * hl * 0.7071, ey = py + (hy - dy / l) * hl * 0.7071;
        stroke(c, (double[]){ px, py, ex, ey }, 2, 1.2, COL_GROUND, 0);
    }
}

/* Pin support: triangle below (px, py) on a hatched ground line. */
static void pin_support(rjr_context *c, double px, double py, double s)
{
    double hb = 0.62 * s, tri_pts[8];
    tri(c, px, py, px - hb, py + s, px + hb, py + s, COL_GROUNDF);
    tri_pts[0] = px - hb; tri_pts[1] = py + s; tri_pts[2] = px; tri_pts[3] = py;
    tri_pts[4] = px + hb; tri_pts[5] = py + s; tri_pts[6] = px - hb; tri_pts[7] = py + s;
    stroke(c, tri_pts, 4, 1.5, COL_GROUND, 1);
    ground_line(c, px - 1.05 * s, py + s, px + 1.05 * s, py + s, 0.0, 1.0, 0.38 * s);
}

static void fmt_len(char *buf, size_t n, double L)
{
    if (L >= 1.0) snprintf(buf, n, "%g m", L);
    else if (L >= 1e-3) snprintf(buf, n, "%g mm", L * 1e3);
    else snprintf(buf, n, "%g um", L * 1e6);
}

static double nice_floor(double v)
{
    double e = pow(10.0, floor(log10(v))), f = v / e;
    return (f >= 5.0 ? 5.0 : (f >= 2.0 ? 2.0 : 1.0)) * e;
}

static double joint_ref_angle(const rj_model *m, const rj_state *s, const rj_joint_def *jd)
{
    int nn, n1, nb;
    double a[2], b[2];
    if (jd->body1 < 0) return jd->ground_angle;
    nn = rj_link_node_count(m, jd->body1);
    n1 = jd->node1 < 0 ? nn - 1 : jd->node1;
    nb = n1 > 0 ? n1 - 1 : 1;
    rj_node_position(m, s, jd->body1, n1, a);
    rj_node_position(m, s, jd->body1, nb, b);
    return atan2(b[1] - a[1], b[0] - a[0]);
}

/* ---- Frame aids: stacks, legend, joint labels, text line -------------------------------- */

static int clip_seg(double *t0, double *t1, double x0, double y0, double x1, double y1, double xa, double ya, double xb, double yb);

/* One frame's drawing context, shared by the passes of rjr_draw_scene: the transform, the
   overlay font, the reserved text band and the per-link offsets of separated stacks. */
typedef struct frame_ctx {
    const rj_model *m;
    const rj_state *s;
    const rjr_view *v;
    scene_xf t;
    double f;                  /* overlay font (capital height), px */
    double band;               /* reserved text band height, 0 none */
    const double *off;         /* per link (x, y) pixel offset, NULL none */
} frame_ctx;

/* Rectangles are {x0, y0, x1, y1} in pixels. */
static double rect_overlap(const double a[4], const double b[4])
{
    double w = fmin(a[2], b[2]) - fmax(a[0], b[0]);
    double h = fmin(a[3], b[3]) - fmax(a[1], b[1]);
    if (w <= 0 || h <= 0)
        return 0.0;
    return w * h;
}

/* Distance from point (x, y) to rectangle r (0 inside). */
static double point_rect_gap(double x, double y, const double r[4])
{
    double dx = fmax(0.0, fmax(r[0] - x, x - r[2]));
    double dy = fmax(0.0, fmax(r[1] - y, y - r[3]));
    return sqrt(dx * dx + dy * dy);
}

/* Gap between two rectangles (0 when they touch or overlap). */
static double rect_gap(const double a[4], const double b[4])
{
    double dx = fmax(0.0, fmax(a[0] - b[2], b[0] - a[2]));
    double dy = fmax(0.0, fmax(a[1] - b[3], b[1] - a[3]));
    return sqrt(dx * dx + dy * dy);
}

/* Node k of link l in pixels, moved by the link's stack offset. */
static void node_px(const frame_ctx *fc, int l, int k, double *x, double *y)
{
    double w[2];
    rj_node_position(fc->m, fc->s, l, k, w);
    w2p(&fc->t, w, x, y);
    if (!fc->off)
        return;
    *x += fc->off[2 * l];
    *y += fc->off[2 * l + 1];
}

/* All nodes of link l in pixels into p[2 * nodes]. */
static void link_px(const frame_ctx *fc, int l, double *p)
{
    int k, nn = rj_link_node_count(fc->m, l);
    for (k = 0; k < nn; k++)
        node_px(fc, l, k, &p[2 * k], &p[2 * k + 1]);
}

/* Width of a link's dark outline. Separated stacks get at least 1 px so that the line
   between two panels survives anti-aliasing. */
static double outline_px(double th, const rjr_view *v)
{
    if (th >= 6)
        return 1.2;
    return v->separate_stacked ? 1.0 : 0.8;
}

/* The normal of direction (ux, uy) that points right or down on screen (nx + ny > 0):
   links stacked on one another all move to the same side, whichever way each one runs. */
static void stack_normal(double ux, double uy, double *nx, double *ny)
{
    *nx = -uy;
    *ny = ux;
    if (*nx + *ny < 0 || (*nx + *ny == 0 && *nx < 0)) {
        *nx = -*nx;
        *ny = -*ny;
    }
}

/* Centre-line distance of two links drawn side by side: half of each thickness and both
   outlines, so that the two dark outlines meet between the fills. */
static double stack_gap(const frame_ctx *fc, int a, int b)
{
    double ta = link_thickness_px(fc->m, a, fc->v);
    double tb = link_thickness_px(fc->m, b, fc->v);
    return 0.5 * (ta + tb) + outline_px(ta, fc->v) + outline_px(tb, fc->v);
}

/* Extent of link b's nodes in the frame of link a's chord (origin a0, direction u, normal
   n): along u in e[0..1], across in e[2..3]. */
static void stack_extent(const frame_ctx *fc, int b, const double a0[2], const double u[2], const double n[2], double e[4])
{
    int k, nb = rj_link_node_count(fc->m, b);
    e[0] = e[2] = HUGE_VAL;
    e[1] = e[3] = -HUGE_VAL;
    for (k = 0; k < nb; k++) {
        double x, y, along, across;
        node_px(fc, b, k, &x, &y);
        along = (x - a0[0]) * u[0] + (y - a0[1]) * u[1];
        across = (x - a0[0]) * n[0] + (y - a0[1]) * n[1];
        e[0] = fmin(e[0], along);
        e[1] = fmax(e[1], along);
        e[2] = fmin(e[2], across);
        e[3] = fmax(e[3], across);
    }
}

/* How far link b must move along the normal n of link a's chord to lie beside a rather
   than on it. b lies on a when its nodes project onto a's chord over at least half the
   shorter length and the middle of their lateral spread is within the side-by-side gap.
   The push fades out while b turns away (lateral spread from one gap to two), so that a
   fold that opens does not jump. */
static double stack_push(const frame_ctx *fc, int a, int b, double n[2])
{
    double a0[2], a1[2], u[2], e[4], la, over, mid, gap, w;
    n[0] = 0.0;
    n[1] = 0.0;
    node_px(fc, a, 0, &a0[0], &a0[1]);
    node_px(fc, a, rj_link_node_count(fc->m, a) - 1, &a1[0], &a1[1]);
    la = hypot(a1[0] - a0[0], a1[1] - a0[1]);
    if (!(la > 1.0))
        return 0.0;
    u[0] = (a1[0] - a0[0]) / la;
    u[1] = (a1[1] - a0[1]) / la;
    stack_normal(u[0], u[1], &n[0], &n[1]);
    stack_extent(fc, b, a0, u, n, e);
    over = fmin(e[1], la) - fmax(e[0], 0.0);
    if (!(e[1] - e[0] > 1.0) || over < 0.5 * fmin(la, e[1] - e[0]))
        return 0.0;
    mid = 0.5 * (e[2] + e[3]);
    gap = stack_gap(fc, a, b);
    if (mid <= -gap || mid >= gap)
        return 0.0;
    w = fmin(1.0, (2.0 * gap - (e[3] - e[2])) / gap);
    if (w <= 0)
        return 0.0;
    return w * (gap - mid);
}

/* Stack offsets into c->po: in link order, each link is pushed off every earlier link it
   lies on, once, so a stowed stack fans out to one side like the real one. */
static int stack_offsets(rjr_context *c, frame_ctx *fc)
{
    int a, b, nl = rj_model_link_count(fc->m);
    if (grow(&c->po, &c->capo, (size_t)nl))
        return -1;
    memset(c->po, 0, (size_t)nl * 2 * sizeof(double));
    fc->off = c->po;
    for (b = 1; b < nl; b++)
        for (a = 0; a < b; a++) {
            double n[2], push = stack_push(fc, a, b, n);
            c->po[2 * b] += push * n[0];
            c->po[2 * b + 1] += push * n[1];
        }
    return 0;
}

/* A joint's pin radius and limit-arc radius in pixels, as the joint pass draws them. */
static void joint_radii(const frame_ctx *fc, int j, double *rp, double *R)
{
    const rj_joint_def *jd = rj_model_joint_def(fc->m, j);
    double th = link_thickness_px(fc->m, jd->body2, fc->v);
    if (jd->body1 >= 0)
        th = fmax(th, link_thickness_px(fc->m, jd->body1, fc->v));
    *rp = th * 0.3 < 3.5 ? 3.5 : (th * 0.3 > 12 ? 12 : th * 0.3);
    *R = th * 0.5 + 12 > 20 ? th * 0.5 + 12 : 20;
}

/* Pixels of a tip mass in r grown by margin: its square (half side 0.85 x thickness, at
   least 5 px, as drawn) as the disc around it, how deep r reaches into it times its
   diameter. */
static double tip_cover(const frame_ctx *fc, int l, const double r[4], double margin)
{
    double x, y, rad = 1.42 * fmax(5.0, 0.85 * link_thickness_px(fc->m, l, fc->v)) + margin;
    if (!(rj_model_link_def(fc->m, l)->tip_mass > 0))
        return 0.0;
    node_px(fc, l, rj_link_node_count(fc->m, l) - 1, &x, &y);
    return 2.0 * rad * fmax(0.0, rad - point_rect_gap(x, y, r));
}

/* Pixels of links that fall in rectangle r grown by margin: for every element, the length
   inside r (grown by half the link's thickness) times the thickness; and the tip masses. */
static double links_cover(const frame_ctx *fc, const double r[4], double margin)
{
    int l, k, nl = rj_model_link_count(fc->m);
    double sum = 0.0;
    for (l = 0; l < nl; l++) {
        double th = link_thickness_px(fc->m, l, fc->v), e = 0.5 * th + margin, x0, y0;
        node_px(fc, l, 0, &x0, &y0);
        for (k = 1; k < rj_link_node_count(fc->m, l); k++) {
            double x1, y1, t0, t1;
            node_px(fc, l, k, &x1, &y1);
            if (clip_seg(&t0, &t1, x0, y0, x1, y1, r[0] - e, r[1] - e, r[2] + e, r[3] + e))
                sum += (t1 - t0) * hypot(x1 - x0, y1 - y0) * th;
            x0 = x1;
            y0 = y1;
        }
        sum += tip_cover(fc, l, r, margin);
    }
    return sum;
}

/* Pixels of joint symbols in r grown by margin: the pin, or the limit arc and needle, as
   a disc (how deep r reaches into it, times its diameter); the ground support of a ground
   joint as its box. */
static double joints_cover(const frame_ctx *fc, const double r[4], double margin)
{
    int j, nj = rj_model_joint_count(fc->m);
    double sum = 0.0;
    for (j = 0; j < nj; j++) {
        const rj_joint_def *jd = rj_model_joint_def(fc->m, j);
        double p[2], x, y, rp, R, rad, sym[4];
        joint_radii(fc, j, &rp, &R);
        rj_joint_position(fc->m, fc->s, j, p);
        w2p(&fc->t, p, &x, &y);
        rad = (fc->v->show_limits ? R + 7 : rp) + margin;
        sum += 2.0 * rad * fmax(0.0, rad - point_rect_gap(x, y, r));
        if (jd->body1 >= 0 || !fc->v->show_ground)
            continue;
        /* pin_support: a triangle of height sz on a hatched line 2.1 sz wide */
        p[0] = jd->ground_x;
        p[1] = jd->ground_y;
        w2p(&fc->t, p, &x, &y);
        rad = fmin(48.0, fmax(14.0, link_thickness_px(fc->m, jd->body2, fc->v) * 1.1));
        sym[0] = x - 1.1 * rad - margin;
        sym[1] = y - margin;
        sym[2] = x + 1.1 * rad + margin;
        sym[3] = y + 1.45 * rad + margin;
        sum += rect_overlap(sym, r);
    }
    return sum;
}

/* Pixel bounding box of the mechanism: every node (moved by its stack offset). */
static void mechanism_box(const frame_ctx *fc, double b[4])
{
    int l, k, nl = rj_model_link_count(fc->m);
    b[0] = b[1] = HUGE_VAL;
    b[2] = b[3] = -HUGE_VAL;
    for (l = 0; l < nl; l++)
        for (k = 0; k < rj_link_node_count(fc->m, l); k++) {
            double x, y;
            node_px(fc, l, k, &x, &y);
            b[0] = fmin(b[0], x);
            b[1] = fmin(b[1], y);
            b[2] = fmax(b[2], x);
            b[3] = fmax(b[3], y);
        }
}

/* Size of the small font of legends and joint labels. */
static double small_font(double f)
{
    return fmax(9.0, floor(f * 0.8 + 0.5));
}

/* Bottom of the line that holds the time stamp and caption, or of the band. */
static double top_text_bottom(const frame_ctx *fc)
{
    double pad = floor(fc->f * 0.8);
    if (fc->band > 0)
        return fc->band;
    if (!fc->v->show_time && !fc->v->caption)
        return 0.0;
    return pad + ceil(fc->f * 4.0 / 3.0);
}

/* Top of the scale bar and its label (0 rows when there is none). */
static double scale_top(const rjr_context *c, const frame_ctx *fc)
{
    if (!fc->v->show_scale)
        return c->height;
    return c->height - ceil(fc->f * 2.2) - 9;
}

/* Rectangles that overlays keep out of: the time stamp and caption line, the scale bar
   (with the width of a fifth of the image it takes) and, once placed, the legend. */
typedef struct keep_out {
    double r[3][4];
    int n;
} keep_out;

static void keep_out_init(const rjr_context *c, const frame_ctx *fc, keep_out *k)
{
    k->n = 0;
    k->r[k->n][0] = 0;
    k->r[k->n][1] = 0;
    k->r[k->n][2] = c->width;
    k->r[k->n][3] = top_text_bottom(fc);
    k->n++;
    k->r[k->n][0] = 0;
    k->r[k->n][1] = scale_top(c, fc);
    k->r[k->n][2] = floor(fc->f * 0.8) + c->width * 0.25 + fc->f * 3;
    k->r[k->n][3] = c->height;
    k->n++;
}

/* ---- Legend: the joint colours ---- */

static const struct { rjr_rgb col; const char *text; } legend_rows[3] = {
    { COL_FREE, "joint free" },
    { COL_LIMIT, "joint at a limit" },
    { COL_LOCKED, "joint locked" },
};

/* Legend box size for font fs: a pin-and-needle sample and a text per row. */
static void legend_size(double fs, double *w, double *h)
{
    double tw = 0.0;
    int i;
    for (i = 0; i < 3; i++)
        tw = fmax(tw, rjr_text_width(legend_rows[i].text, fs));
    *w = 2 * floor(fs * 0.8) + floor(fs * 2.6) + floor(fs * 0.7) + ceil(tw);
    *h = 3 * floor(fs * 1.8) + floor(fs * 0.8);
}

/* Legend rectangle in corner k (0 top-right, 1 top-left, 2 bottom-right, 3 bottom-left),
   below the time stamp and caption line and above the scale bar. */
static void legend_rect(const rjr_context *c, const frame_ctx *fc, int k, double w, double h, double r[4])
{
    double inset = floor(fc->f * 0.8);
    double top = top_text_bottom(fc) > 0 ? top_text_bottom(fc) + floor(0.5 * inset) : inset;
    double bottom = c->height - inset;
    if (k == 3 && fc->v->show_scale)
        bottom = scale_top(c, fc) - floor(0.5 * inset);
    r[0] = (k & 1) ? inset : c->width - inset - w;
    r[1] = (k & 2) ? bottom - h : top;
    r[2] = r[0] + w;
    r[3] = r[1] + h;
}

/* The legend's corner: the one whose rectangle covers the fewest link and joint pixels;
   of equal ones, the farthest from the mechanism's bounding box; then the first in the
   order top-right, top-left, bottom-right, bottom-left. 0 when no corner has room. */
static int legend_place(const rjr_context *c, const frame_ctx *fc, double r[4])
{
    double w, h, box[4], best = HUGE_VAL, far = -1.0;
    int k, found = 0;
    legend_size(small_font(fc->f), &w, &h);
    if (w > c->width - 2 * floor(fc->f * 0.8) || h > 0.5 * c->height)
        return 0;
    mechanism_box(fc, box);
    for (k = 0; k < 4; k++) {
        double q[4], cover, gap;
        legend_rect(c, fc, k, w, h, q);
        cover = links_cover(fc, q, 2.0) + joints_cover(fc, q, 2.0);
        gap = rect_gap(q, box);
        if (cover > best + 0.5 || (cover > best - 0.5 && gap <= far + 0.5))
            continue;
        best = cover;
        far = gap;
        memcpy(r, q, sizeof q);
        found = 1;
    }
    return found;
}

/* The legend in rectangle r: white box, grey border, per row a needle and a pin in the
   colours of the joint pass (the free pin has a dark ring) and its meaning. The needles
   are whole-pixel rectangles, so their colours appear exactly. */
static void draw_legend(rjr_context *c, const double r[4], double fs)
{
    double pad = floor(fs * 0.8), row = floor(fs * 1.8), sample = floor(fs * 2.6);
    double rp = floor(fs * 0.35 + 0.5), x = r[0] + pad;
    int i;
    rjr_rect(c, r[0], r[1], r[2] - r[0], r[3] - r[1], 0xffffff);
    rect_outline(c, r[0], r[1], r[2] - r[0], r[3] - r[1], 1, 0xa6a6a6);
    for (i = 0; i < 3; i++) {
        double y = r[1] + floor(0.5 * pad) + row * i + floor(0.5 * row);
        rjr_rgb ring = i == 0 ? COL_INK : legend_rows[i].col;
        rjr_rect(c, x + rp, y - 1, sample - rp, 2, legend_rows[i].col);
        rjr_disc(c, x + rp, y, rp, ring);
        rjr_disc(c, x + rp, y, rp - (rp * 0.35 < 1.2 ? 1.2 : rp * 0.35), 0xffffff);
        rjr_text(c, x + sample + floor(fs * 0.7), y, fs, 0.0, RJR_LEFT | RJR_MIDDLE, COL_INK, legend_rows[i].text);
    }
}

/* ---- Joint labels ---- */

/* Joint j's label: its name, its running angle in degrees ("h2 317.5 deg"), or both;
   the running angle because limits and springs act on it and it does not jump at
   0/360 deg, so a joint folded at 360 deg reads 360, as its scene file says. */
static void joint_label_text(const frame_ctx *fc, int j, char *buf, size_t n)
{
    const char *name = fc->v->joint_names ? fc->v->joint_names[j] : NULL;
    char ang[48], *d;
    ang[0] = 0;
    if (fc->v->show_joint_angles) {
        snprintf(ang, sizeof ang, "%.1f deg", rj_deg(rj_joint_theta_running(fc->m, fc->s, j)));
        /* a locale's decimal comma back to a point, and no "-0.0" */
        for (d = ang; *d; d++)
            if (*d == ',')
                *d = '.';
        if (strcmp(ang, "-0.0 deg") == 0)
            memmove(ang, ang + 1, strlen(ang));
    }
    snprintf(buf, n, "%s%s%s", name ? name : "", name && ang[0] ? " " : "", ang);
}

/* The preferred side for joint j's label: away from the bisector of its two links (body 1
   along the reference direction, body 2 along the needle), or, when they are straight,
   the side that is up on screen. */
static void label_away(const frame_ctx *fc, int j, double u[2])
{
    const rj_joint_def *jd = rj_model_joint_def(fc->m, j);
    double ref = joint_ref_angle(fc->m, fc->s, jd);
    double a2 = ref + rj_joint_theta(fc->m, fc->s, j);
    double bx = cos(ref) + cos(a2), by = -sin(ref) - sin(a2), bl = hypot(bx, by);
    if (bl > 1e-6) {
        u[0] = -bx / bl;
        u[1] = -by / bl;
        return;
    }
    u[0] = sin(ref);
    u[1] = cos(ref);
    if (u[1] > 0 || (u[1] == 0 && u[0] < 0)) {
        u[0] = -u[0];
        u[1] = -u[1];
    }
}

/* A tw x th box on the side u of (x, y): the ray from the point along u enters it at
   distance r0 (a diagonal box may come nearer elsewhere; the score sees that). */
static void label_box(double x, double y, const double u[2], double r0, double tw, double th, double b[4])
{
    double ex = fabs(u[0]) > 1e-9 ? 0.5 * tw / fabs(u[0]) : HUGE_VAL;
    double ey = fabs(u[1]) > 1e-9 ? 0.5 * th / fabs(u[1]) : HUGE_VAL;
    double reach = r0 + fmin(ex, ey);
    double cx = x + u[0] * reach, cy = y + u[1] * reach;
    b[0] = floor(cx - 0.5 * tw);
    b[1] = floor(cy - 0.5 * th);
    b[2] = b[0] + tw;
    b[3] = b[1] + th;
}

/* What a label at b would hide or leave: link pixels near it (four times: text on a link
   is worse than text near a limit arc), joint symbol pixels, and ten times the area it
   shares with earlier labels, the keep-out rectangles, or the outside of the image (or the
   band). */
static double label_score(const rjr_context *c, const frame_ctx *fc, const double b[4], const double *placed, int np, const keep_out *k)
{
    double score = 4.0 * links_cover(fc, b, 3.0) + joints_cover(fc, b, 1.0), img[4];
    int i;
    img[0] = 0;
    img[1] = fc->band;
    img[2] = c->width;
    img[3] = c->height;
    score += 10.0 * ((b[2] - b[0]) * (b[3] - b[1]) - rect_overlap(b, img));
    for (i = 0; i < np; i++)
        score += 10.0 * rect_overlap(b, placed + 4 * i);
    for (i = 0; i < k->n; i++)
        score += 10.0 * rect_overlap(b, k->r[i]);
    return score;
}

/* Joint j's label box: of 80 candidates (16 directions, turning from the preferred side
   by 22.5 deg either way, at five distances from just beyond the limit arc to 3.5 times
   that, for joints crowded together), the first with the lowest score. */
static void label_place(const rjr_context *c, const frame_ctx *fc, int j, double tw, double th, const keep_out *k, double best[4])
{
    static const double reach[5] = { 1.0, 1.5, 2.0, 2.75, 3.5 };
    double p[2], x, y, rp, R, r0, away[2], low = HUGE_VAL;
    int i, ring;
    joint_radii(fc, j, &rp, &R);
    r0 = fc->v->show_limits ? R + 9 : rp + 4;   /* past the needle (R + 7) */
    rj_joint_position(fc->m, fc->s, j, p);
    w2p(&fc->t, p, &x, &y);
    label_away(fc, j, away);
    for (ring = 0; ring < 5; ring++)
        for (i = 0; i < 16; i++) {
            /* 0, +22.5, -22.5, +45, -45, ... 180 deg */
            double a = (i % 2 ? 1.0 : -1.0) * ((i + 1) / 2) * M_PI / 8.0, u[2], b[4], sc;
            u[0] = away[0] * cos(a) - away[1] * sin(a);
            u[1] = away[0] * sin(a) + away[1] * cos(a);
            label_box(x, y, u, r0 * reach[ring], tw, th, b);
            sc = label_score(c, fc, b, c->pl, j, k);
            if (sc >= low)
                continue;
            low = sc;
            memcpy(best, b, sizeof b);
        }
}

/* Every joint's label in the small font, placed in joint order (each avoids the earlier
   ones); boxes go to c->pl. */
static int draw_joint_labels(rjr_context *c, const frame_ctx *fc, const keep_out *k)
{
    int j, nj = rj_model_joint_count(fc->m);
    double fs = small_font(fc->f);
    if (grow(&c->pl, &c->capl, (size_t)nj * 2))
        return -1;
    for (j = 0; j < nj; j++) {
        char text[160];
        double *b = c->pl + 4 * j;
        joint_label_text(fc, j, text, sizeof text);
        b[0] = b[1] = b[2] = b[3] = -1e9;
        if (!text[0])
            continue;
        label_place(c, fc, j, ceil(rjr_text_width(text, fs)) + 2, ceil(fs * 4.0 / 3.0) + 2, k, b);
        rjr_text(c, b[0] + 1, b[1] + 1, fs, 0.0, RJR_LEFT | RJR_TOP, COL_INK, text);
    }
    return 0;
}

/* ---- Time stamp and caption ---- */

/* The caption at most room wide: at full size when it fits, else smaller down to 0.7 of
   the size, else at 0.7 with its end replaced by "..." (in buf). */
static const char *fit_caption(const char *s, double room, double f, char *buf, size_t n, double *size)
{
    double w = rjr_text_width(s, f);
    size_t len;
    *size = f;
    if (w <= room)
        return s;
    *size = f * room / w;
    if (*size >= 0.7 * f)
        return s;
    *size = 0.7 * f;
    len = strlen(s) < n - 4 ? strlen(s) : n - 4;
    /* drop characters until the rest and "..." fit */
    do {
        memcpy(buf, s, len);
        memcpy(buf + len, "...", 4);
    } while (len-- > 0 && rjr_text_width(buf, *size) > room);
    if (rjr_text_width(buf, *size) > room)
        buf[0] = 0;
    return buf;
}

/* The time stamp top-left and the caption top-right on one line; the caption takes the
   width the time stamp leaves, with a gap of one capital height, so they never overlap. */
static void draw_top_texts(rjr_context *c, const frame_ctx *fc)
{
    double f = fc->f, pad = floor(f * 0.8), left = pad, size;
    char buf[64], cut[256];
    const char *cap;
    if (fc->v->show_time) {
        snprintf(buf, sizeof buf, "t = %.4f s", rj_state_time(fc->s));
        left += rjr_text(c, pad, pad, f, 0.0, RJR_LEFT | RJR_TOP, COL_INK, buf) + f;
    }
    if (!fc->v->caption)
        return;
    cap = fit_caption(fc->v->caption, c->width - pad - left, f, cut, sizeof cut, &size);
    rjr_text(c, c->width - pad, pad, size, 0.0, RJR_RIGHT | RJR_TOP, COL_INK, cap);
}

/* The frame's transform, font, band and, for separated stacks, the link offsets. */
static int frame_setup(rjr_context *c, const rj_model *m, const rj_state *s, const rjr_view *v, frame_ctx *fc)
{
    fc->m = m;
    fc->s = s;
    fc->v = v;
    fc->f = view_font(c, v);
    fc->band = band_of(c, v, fc->f);
    fc->off = NULL;
    scene_transform(c, v, fc->band, &fc->t);
    if (v->separate_stacked && stack_offsets(c, fc) != 0) {
        ctx_fail(c, "out of memory");
        return -1;
    }
    return 0;
}

int rjr_draw_scene(rjr_context *c, const rj_model *m, const rj_state *s, const rjr_view *v)
{
    int nl, nj, l, j, k, has_legend = 0;
    scene_xf t;
    frame_ctx fc;
    keep_out ko;
    double f, tmax = 0.0, legend[4];
    char buf[64];
    if (!c->in_frame) { set_err(c->err, sizeof c->err, "rjr_draw_scene: no open frame"); return -1; }
    if (!(v->mpp > 0) || !isfinite(v->cx) || !isfinite(v->cy)) { ctx_fail(c, "rjr_draw_scene: bad view"); return -1; }
    nl = rj_model_link_count(m);
    nj = rj_model_joint_count(m);
    if (frame_setup(c, m, s, v, &fc) != 0)
        return -1;
    t = fc.t;
    f = fc.f;
    /* the band belongs to the texts: nothing of the scene is drawn into it */
    if (fc.band > 0)
        rjr_clip(c, 0, (int)fc.band, c->width, c->height - (int)fc.band);
    for (l = 0; l < nl; l++) {
        double th = link_thickness_px(m, l, v);
        if (th > tmax) tmax = th;
    }

    /* Ground: pins of ground joints, supports of root links. */
    if (v->show_ground) {
        for (j = 0; j < nj; j++) {
            const rj_joint_def *jd = rj_model_joint_def(m, j);
            double g[2], px, py, th;
            if (jd->body1 >= 0) continue;
            th = link_thickness_px(m, jd->body2, v);
            g[0] = jd->ground_x; g[1] = jd->ground_y;
            w2p(&t, g, &px, &py);
            pin_support(c, px, py, th * 1.1 < 14 ? 14 : (th * 1.1 > 48 ? 48 : th * 1.1));
        }
        for (l = 0; l < nl; l++) {
            const rj_link_def *ld = rj_model_link_def(m, l);
            int is_body2 = 0;
            double p0[2], p1[2], x0, y0, x1, y1, dx, dy, dl, th, hl;
            for (j = 0; j < nj; j++)
                if (rj_model_joint_def(m, j)->body2 == l) is_body2 = 1;
            if (ld->root == RJ_ROOT_FREE || (is_body2 && ld->root != RJ_ROOT_FIXED)) continue;
            th = link_thickness_px(m, l, v);
            rj_node_position(m, s, l, 0, p0);
            rj_node_position(m, s, l, ld->root == RJ_ROOT_FIXED ? rj_link_node_count(m, l) - 1 : 1, p1);
            w2p(&t, p0, &x0, &y0);
            w2p(&t, p1, &x1, &y1);
            if (ld->root == RJ_ROOT_FIXED) {
                /* the whole link is ground: hatched line along its lower side */
                double nx, ny, off;
                dx = x1 - x0; dy = y1 - y0; dl = sqrt(dx * dx + dy * dy);
                if (!(dl > 0)) continue;
                nx = -dy / dl; ny = dx / dl;
                if (ny < 0 || (ny == 0 && nx < 0)) { nx = -nx; ny = -ny; }
                off = 0.5 * th + 1.5;
                ground_line(c, x0 + nx * off, y0 + ny * off, x1 + nx * off, y1 + ny * off, nx, ny, th * 0.6 < 7 ? 7 : (th * 0.6 > 16 ? 16 : th * 0.6));
                continue;
            }
            if (ld->root == RJ_ROOT_PINNED) {
                pin_support(c, x0, y0, th * 1.1 < 14 ? 14 : (th * 1.1 > 48 ? 48 : th * 1.1));
                continue;
            }
            dx = x1 - x0; dy = y1 - y0; dl = sqrt(dx * dx + dy * dy);
            if (!(dl > 0)) { dx = 1; dy = 0; dl = 1; }
            dx /= dl; dy /= dl;
            hl = 0.5 * th + (th * 0.5 > 8 ? th * 0.5 : 8);   /* half length of the wall */
            /* wall across the root, hatched on the side away from the link */
            ground_line(c, x0 - dx * 1.0 + dy * hl, y0 - dy * 1.0 - dx * hl,
                        x0 - dx * 1.0 - dy * hl, y0 - dy * 1.0 + dx * hl, -dx, -dy, hl * 0.45 < 6 ? 6 : hl * 0.45);
        }
    }

    /* Links: outline strip, then the fill strip on top (separated stacks: always both). */
    for (l = 0; l < nl; l++) {
        int nn = rj_link_node_count(m, l);
        double th = link_thickness_px(m, l, v), ow = outline_px(th, v), *p, ex, ey, el;
        rjr_rgb fill = link_fill[l % (int)(sizeof link_fill / sizeof link_fill[0])];
        if (grow(&c->pa, &c->capa, (size_t)nn)) { ctx_fail(c, "out of memory"); return -1; }
        p = c->pa;
        link_px(&fc, l, p);
        if (th < 4.5 && !v->separate_stacked) {   /* thin: a single dark strip */
            stroke(c, p, nn, th, darker(fill, 0.55), 0);
            continue;
        }
        /* extend the ends by the outline width for the outline pass */
        ex = p[2] - p[0]; ey = p[3] - p[1]; el = sqrt(ex * ex + ey * ey);
        if (el > 0) { p[0] -= ex / el * ow; p[1] -= ey / el * ow; }
        ex = p[2 * nn - 2] - p[2 * nn - 4]; ey = p[2 * nn - 1] - p[2 * nn - 3]; el = sqrt(ex * ex + ey * ey);
        if (el > 0) { p[2 * nn - 2] += ex / el * ow; p[2 * nn - 1] += ey / el * ow; }
        stroke(c, p, nn, th + 2 * ow, darker(fill, 0.45), 0);
        link_px(&fc, l, p);
        stroke(c, p, nn, th, fill, 0);
    }

    if (v->show_nodes)
        for (l = 0; l < nl; l++)
            for (k = 0; k < rj_link_node_count(m, l); k++) {
                double x, y;
                node_px(&fc, l, k, &x, &y);
                rjr_disc(c, x, y, 1.6, COL_INK);
            }

    /* Tip masses: dark squares along the last element. */
    for (l = 0; l < nl; l++) {
        const rj_link_def *ld = rj_model_link_def(m, l);
        int nn = rj_link_node_count(m, l);
        double ax, ay, bx, by, dx, dy, dl, h;
        if (!(ld->tip_mass > 0)) continue;
        node_px(&fc, l, nn - 2, &ax, &ay);
        node_px(&fc, l, nn - 1, &bx, &by);
        dx = bx - ax; dy = by - ay; dl = sqrt(dx * dx + dy * dy);
        if (!(dl > 0)) { dx = 1; dy = 0; dl = 1; }
        dx /= dl; dy /= dl;
        h = 0.5 * link_thickness_px(m, l, v) * 1.7;
        if (h < 5) h = 5;
        quad(c, bx + (dx - dy) * h, by + (dy + dx) * h, bx + (-dx - dy) * h, by + (-dy + dx) * h,
             bx + (-dx + dy) * h, by + (-dy - dx) * h, bx + (dx + dy) * h, by + (dy - dx) * h, COL_INK);
        h -= 1.5;
        quad(c, bx + (dx - dy) * h, by + (dy + dx) * h, bx + (-dx - dy) * h, by + (-dy + dx) * h,
             bx + (-dx + dy) * h, by + (-dy - dx) * h, bx + (dx + dy) * h, by + (dy - dx) * h, 0x5a5a5a);
    }

    /* Joints: limit arc, stops, needle, pin. */
    for (j = 0; j < nj; j++) {
        const rj_joint_def *jd = rj_model_joint_def(m, j);
        double p[2], x, y, th = link_thickness_px(m, jd->body2, v), R, rp, ref, a0, a1, ang;
        int flag = rj_joint_flag(m, s, j);
        rjr_rgb fc = flag == RJ_LOCKED ? COL_LOCKED : (flag == RJ_FREE ? COL_FREE : COL_LIMIT);
        if (jd->body1 >= 0) {
            double t1 = link_thickness_px(m, jd->body1, v);
            if (t1 > th) th = t1;
        }
        rj_joint_position(m, s, j, p);
        w2p(&t, p, &x, &y);
        rp = th * 0.3 < 3.5 ? 3.5 : (th * 0.3 > 12 ? 12 : th * 0.3);
        if (v->show_limits) {
            R = th * 0.5 + 12 > 20 ? th * 0.5 + 12 : 20;
            ref = joint_ref_angle(m, s, jd);
            a0 = jd->has_reverse ? jd->reverse : 0.0;
            a1 = jd->has_forward ? jd->forward : 2.0 * M_PI;
            if (a1 < a0) a1 += 2.0 * M_PI;
            /* reference direction: short thin tick */
            rjr_line(c, x + (R - 5) * cos(ref), y - (R - 5) * sin(ref), x + (R + 3) * cos(ref), y - (R + 3) * sin(ref), 1.0, COL_ARC);
            arc_stroke(c, x, y, R, ref + a0, ref + a1, 2.0, COL_ARC, 0);
            if (jd->has_reverse) {
                ang = ref + jd->reverse;
                rjr_line(c, x + (R - 5) * cos(ang), y - (R - 5) * sin(ang), x + (R + 5) * cos(ang), y - (R + 5) * sin(ang), 2.5,
                         (flag == RJ_AT_REVERSE) ? COL_LIMIT : (flag == RJ_LOCKED ? COL_LOCKED : COL_STOP));
            }
            if (jd->has_forward) {
                ang = ref + jd->forward;
                rjr_line(c, x + (R - 5) * cos(ang), y - (R - 5) * sin(ang), x + (R + 5) * cos(ang), y - (R + 5) * sin(ang), 2.5,
                         (flag == RJ_AT_FORWARD) ? COL_LIMIT : (flag == RJ_LOCKED ? COL_LOCKED : COL_STOP));
            }
            ang = ref + rj_joint_theta(m, s, j);
            rjr_line(c, x + rp * cos(ang), y - rp * sin(ang), x + (R + 7) * cos(ang), y - (R + 7) * sin(ang), 2.2, fc);
        }
        rjr_disc(c, x, y, rp, flag == RJ_FREE ? COL_INK : fc);
        rjr_disc(c, x, y, rp - (rp * 0.35 < 1.2 ? 1.2 : rp * 0.35), 0xffffff);
    }

    /* Joint labels avoid the links, each other, the texts, the scale bar and the legend,
       which is placed first for that. */
    keep_out_init(c, &fc, &ko);
    if (v->show_legend)
        has_legend = legend_place(c, &fc, legend);
    if (has_legend) {
        memcpy(ko.r[ko.n], legend, sizeof legend);
        ko.n++;
    }
    if ((v->joint_names || v->show_joint_angles) && draw_joint_labels(c, &fc, &ko) != 0) {
        ctx_fail(c, "out of memory");
        return -1;
    }
    if (fc.band > 0)
        rjr_clip(c, 0, 0, 0, 0);

    /* Overlays. */
    draw_top_texts(c, &fc);
    if (v->show_scale) {
        double L = nice_floor(t.mpp * c->width * 0.2), len = L / t.mpp;
        double x0 = floor(f * 0.8), y0 = c->height - floor(f * 0.9);
        rjr_rect(c, x0, y0 - 3, len, 3, COL_INK);
        rjr_rect(c, x0, y0 - 9, 2, 9, COL_INK);
        rjr_rect(c, x0 + len - 2, y0 - 9, 2, 9, COL_INK);
        fmt_len(buf, sizeof buf, L);
        rjr_text(c, x0 + 0.5 * len, y0 - 9 - floor(0.35 * f), f * 0.9, 0.0, RJR_CENTER | RJR_BASELINE, COL_INK, buf);
    }
    if (has_legend)
        draw_legend(c, legend, small_font(f));
    (void)tmax;
    return c->failed ? -1 : 0;
}

int rjr_draw_state(rjr_context *c, const rj_model *m, const rj_state *s, const rjr_view *v)
{
    int r;
    if (rjr_begin(c, v->background) != 0) return -1;
    r = rjr_draw_scene(c, m, s, v);
    if (rjr_end(c) != 0) return -1;
    return r;
}
#endif /* RJR_NO_SCENE */

/* ---- Plots ------------------------------------------------------------------------------ */

static const rjr_rgb plot_palette[RJR_MAX_SERIES] = {
    0x1f77b4, 0xd62728, 0x2ca02c, 0xff7f0e, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf
};

#define AXIS_MAXT 64
typedef struct axis {
    int log;
    double lo, hi;                 /* in axis space (log10 for log axes) */
    double step;                   /* linear major step */
    double major[AXIS_MAXT];       /* axis-space positions */
    int nmajor;
    double minor[AXIS_MAXT * 2];
    int nminor;
    char label[AXIS_MAXT][24];
} axis;

rjr_plot_def rjr_plot_default(void)
{
    rjr_plot_def d;
    int i;
    memset(&d, 0, sizeof d);
    d.grid = 1;
    d.legend = RJR_LEGEND_TOP_RIGHT;
    for (i = 0; i < RJR_MAX_SERIES; i++) d.series[i].colour = RJR_AUTO_COLOUR;
    return d;
}

static double nice_ceil(double raw)
{
    double e = pow(10.0, floor(log10(raw))), f = raw / e;
    return (f <= 1.0 + 1e-9 ? 1.0 : (f <= 2.0 + 1e-9 ? 2.0 : (f <= 5.0 + 1e-9 ? 5.0 : 10.0))) * e;
}

/* Replaces a locale decimal comma and tidies exponents: "1.5e-05" -> "1.5e-5". */
static void tidy_number(char *s)
{
    char *e, *d;
    for (d = s; *d; d++) if (*d == ',') *d = '.';
    e = strchr(s, 'e');
    if (!e) return;
    d = e + 1;
    if (*d == '+') memmove(d, d + 1, strlen(d + 1) + 1);
    else if (*d == '-') d++;
    while (d[0] == '0' && d[1]) memmove(d, d + 1, strlen(d + 1) + 1);
}

static void fmt_tick(char *buf, size_t n, double v, double step)
{
    double a = fabs(v);
    if (a < step * 1e-6) { v = 0.0; a = 0.0; }
    if ((a >= 1e5 || step < 1e-4) && a > 0) {
        int sig = (int)(floor(log10(a)) - floor(log10(step) + 1e-9)) + 1;
        if (sig < 1) sig = 1;
        if (sig > 15) sig = 15;
        snprintf(buf, n, "%.*e", sig - 1, v);
        /* drop trailing zeros of the mantissa */
        {
            char *e = strchr(buf, 'e'), *z;
            if (e && strchr(buf, '.') && strchr(buf, '.') < e) {
                z = e;
                while (z[-1] == '0') z--;
                if (z[-1] == '.') z--;
                memmove(z, e, strlen(e) + 1);
            }
        }
    } else {
        int dec = (int)-floor(log10(step) + 1e-9);
        if (dec < 0) dec = 0;
        snprintf(buf, n, "%.*f", dec, v);
    }
    tidy_number(buf);
}

static void fmt_pow10(char *buf, size_t n, int k)
{
    if (k >= 0 && k <= 4) snprintf(buf, n, "%.0f", pow(10.0, k));
    else if (k < 0 && k >= -2) snprintf(buf, n, "%.*f", -k, pow(10.0, k));
    else snprintf(buf, n, "1e%d", k);
    tidy_number(buf);
}

/* Data range of one coordinate over all series (finite, > 0 on log axes). */
static int data_range(const rjr_plot_def *d, int which, int log, double *mn, double *mx)
{
    int i, k, any = 0;
    *mn = HUGE_VAL; *mx = -HUGE_VAL;
    for (i = 0; i < d->series_count && i < RJR_MAX_SERIES; i++) {
        const rjr_series *s = &d->series[i];
        const double *v = which ? s->y : s->x;
        if (!s->x || !s->y) continue;
        for (k = 0; k < s->n; k++) {
            double x = s->x[k], y = s->y[k], q = v[k];
            if (!isfinite(x) || !isfinite(y)) continue;
            if ((d->logx && !(x > 0)) || (d->logy && !(y > 0))) continue;
            (void)log;
            if (q < *mn) *mn = q;
            if (q > *mx) *mx = q;
            any = 1;
        }
    }
    return any;
}

static void axis_setup(axis *a, int log, double umin, double umax, int user, double dmin, double dmax, int target)
{
    int i, k;
    a->log = log;
    a->nmajor = a->nminor = 0;
    if (log) {
        double lo, hi;
        int every, k0, k1;
        if (user) { lo = log10(umin); hi = log10(umax); }
        else {
            if (!(dmin > 0)) { dmin = 1.0; dmax = 10.0; }
            lo = floor(log10(dmin) + 1e-9);
            hi = ceil(log10(dmax) - 1e-9);
            if (hi <= lo) { lo -= 0.0; hi = lo + 1.0; }
        }
        a->lo = lo; a->hi = hi;
        k0 = (int)ceil(lo - 1e-9); k1 = (int)floor(hi + 1e-9);
        every = (k1 - k0) / (target > 1 ? target : 1) + 1;
        if (every < 1) every = 1;
        a->step = every;
        for (k = k0; k <= k1 && a->nmajor < AXIS_MAXT; k++) {
            if (((k % every) + every) % every) continue;
            a->major[a->nmajor] = k;
            fmt_pow10(a->label[a->nmajor], sizeof a->label[0], k);
            a->nmajor++;
        }
        if (every > 1)
            for (k = k0; k <= k1 && a->nminor < AXIS_MAXT * 2; k++)
                if (((k % every) + every) % every) a->minor[a->nminor++] = k;
        if (hi - lo <= 8.0 && every == 1)
            for (k = k0 - 1; k <= k1; k++)
                for (i = 2; i <= 9 && a->nminor < AXIS_MAXT * 2; i++) {
                    double v = k + log10((double)i);
                    if (v >= lo - 1e-9 && v <= hi + 1e-9) a->minor[a->nminor++] = v;
                }
    } else {
        double lo, hi, st;
        long i0, i1, q;
        if (user) { lo = umin; hi = umax; }
        else {
            lo = dmin; hi = dmax;
            if (!(hi > lo)) {
                double pad = fabs(lo) > 0 ? fabs(lo) * 0.1 : 1.0;
                if (!isfinite(lo)) { lo = 0.0; pad = 1.0; }
                lo -= pad; hi = lo + 2.0 * pad;
            }
        }
        st = nice_ceil((hi - lo) / (target > 1 ? target : 1));
        if (!user) {
            lo = floor(lo / st + 1e-9) * st;
            hi = ceil(hi / st - 1e-9) * st;
        }
        a->lo = lo; a->hi = hi; a->step = st;
        i0 = (long)ceil(lo / st - 1e-9); i1 = (long)floor(hi / st + 1e-9);
        for (q = i0; q <= i1 && a->nmajor < AXIS_MAXT; q++) {
            a->major[a->nmajor] = (double)q * st;
            fmt_tick(a->label[a->nmajor], sizeof a->label[0], (double)q * st, st);
            a->nmajor++;
        }
    }
}

static double axis_map(const axis *a, double v, double p0, double p1)
{
    double u = a->log ? (v > 0 ? log10(v) : -HUGE_VAL) : v;
    return p0 + (u - a->lo) / (a->hi - a->lo) * (p1 - p0);
}

/* Liang-Barsky clip of segment (x0,y0)-(x1,y1) to [xa,xb]x[ya,yb]; returns 0 if outside. */
static int clip_seg(double *t0, double *t1, double x0, double y0, double x1, double y1, double xa, double ya, double xb, double yb)
{
    double p[4], q[4];
    int i;
    p[0] = -(x1 - x0); q[0] = x0 - xa;
    p[1] = x1 - x0;    q[1] = xb - x0;
    p[2] = -(y1 - y0); q[2] = y0 - ya;
    p[3] = y1 - y0;    q[3] = yb - y0;
    *t0 = 0.0; *t1 = 1.0;
    for (i = 0; i < 4; i++) {
        if (p[i] == 0.0) { if (q[i] < 0) return 0; continue; }
        {
            double r = q[i] / p[i];
            if (p[i] < 0) { if (r > *t1) return 0; if (r > *t0) *t0 = r; }
            else { if (r < *t0) return 0; if (r < *t1) *t1 = r; }
        }
    }
    return 1;
}

static void series_run_flush(rjr_context *c, const rjr_series *s, int k, double w, rjr_rgb col)
{
    if (k < 2) return;
    if (s->dashed) stroke_dashed(c, c->pa, k, w, col, w * 3.5 + 3, w * 2 + 2.5);
    else stroke(c, c->pa, k, w, col, 1);
}

static void draw_series(rjr_context *c, const rjr_plot_def *d, const rjr_series *s, const axis *ax, const axis *ay,
                        double x0, double y0, double x1, double y1, rjr_rgb col)
{
    double w = s->width_px > 0 ? s->width_px : 2.0;
    double cxa = x0 - 20, cya = y0 - 20, cxb = x1 + 20, cyb = y1 + 20;
    double px = 0, py = 0, lx = 0, ly = 0;
    int i, k = 0, prev = 0;
    if (!s->x || !s->y || s->n < 1) return;
    if (grow(&c->pa, &c->capa, (size_t)s->n + 2)) { ctx_fail(c, "out of memory"); return; }
    for (i = 0; i < s->n; i++) {
        double xv = s->x[i], yv = s->y[i], qx, qy, t0, t1;
        int ok = isfinite(xv) && isfinite(yv) && (!d->logx || xv > 0) && (!d->logy || yv > 0);
        if (!ok) { series_run_flush(c, s, k, w, col); k = 0; prev = 0; continue; }
        qx = axis_map(ax, xv, x0, x1);
        qy = axis_map(ay, yv, y1, y0);
        if (s->points && qx >= x0 - 1 && qx <= x1 + 1 && qy >= y0 - 1 && qy <= y1 + 1)
            rjr_disc(c, qx, qy, w * 1.3 > 2.5 ? w * 1.3 : 2.5, col);
        if (!s->no_line && prev) {
            if (!clip_seg(&t0, &t1, px, py, qx, qy, cxa, cya, cxb, cyb)) {
                series_run_flush(c, s, k, w, col); k = 0;
            } else {
                double ax0 = px + (qx - px) * t0, ay0 = py + (qy - py) * t0;
                double bx = px + (qx - px) * t1, by = py + (qy - py) * t1;
                if (k == 0 || t0 > 0.0) {
                    series_run_flush(c, s, k, w, col);
                    c->pa[0] = ax0; c->pa[1] = ay0; k = 1; lx = ax0; ly = ay0;
                }
                /* decimate points closer than 0.25 px, keeping clipped ends */
                if (t1 < 1.0 || i == s->n - 1 || fabs(bx - lx) + fabs(by - ly) >= 0.25) {
                    c->pa[2 * k] = bx; c->pa[2 * k + 1] = by; k++;
                    lx = bx; ly = by;
                }
                if (t1 < 1.0) { series_run_flush(c, s, k, w, col); k = 0; }
            }
        }
        px = qx; py = qy; prev = 1;
    }
    series_run_flush(c, s, k, w, col);
}

/* ---- marker labels: placed so that none hides another ------------------------------
   A label sits at the foot of its dashed line, to the right of it (to the left when it
   would leave the plot), in one of the rows stacked up from the x axis. Its preferred
   row is the marker's index modulo 3, the layout labels always had; a label that would
   overlap one already drawn (locks close in time) takes the next free row up, then the
   other side of its line; only when every row of the plot's height is taken does it keep
   its preferred place. */
typedef struct mark_box { double l, t, r, b; } mark_box;   /* the white backing, px */
typedef struct mark_area { double x0, y0, x1, y1, fs; } mark_area; /* plot area, font px */

/* The backing of a label of width lw at the line xm, in row, on the right or the left. */
static mark_box mark_at(const mark_area *a, double xm, double lw, int row, int right)
{
    mark_box b;
    const double ly = a->y1 - 6 - a->fs - row * floor(a->fs * 1.7);
    const double lx = right ? floor(xm) + 5 : floor(xm) - 4 - lw;
    b.l = lx - 2;
    b.t = ly - 3;
    b.r = b.l + ceil(lw) + 4;
    b.b = b.t + a->fs + 6;
    return b;
}

/* Whether box b overlaps one of the n boxes placed (touching is not overlapping). */
static int mark_hits(const mark_box *b, const mark_box *placed, int n)
{
    int k;
    for (k = 0; k < n; k++)
        if (b->l < placed[k].r && placed[k].l < b->r && b->t < placed[k].b && placed[k].t < b->b) return 1;
    return 0;
}

/* Whether box b lies inside the plot area (rows above the top are not used). */
static int mark_fits(const mark_area *a, const mark_box *b)
{
    return b->t >= a->y0 + 2 && b->l >= a->x0 && b->r <= a->x1;
}

/* The place of a label of width lw at the line xm, its preferred row pref, against the
   n labels placed before it: the preferred row and side when free, else the first free
   of the other rows (low to high) on that side, then of every row on the other side. */
static mark_box mark_place(const mark_area *a, double xm, double lw, int pref,
                             const mark_box *placed, int n)
{
    const int right = xm + 5 + lw <= a->x1 - 3;
    const mark_box first = mark_at(a, xm, lw, pref, right);
    int side, row;
    if (!mark_hits(&first, placed, n)) return first;
    for (side = 0; side < 2; side++) {
        for (row = 0; row < 64; row++) {
            const mark_box b = mark_at(a, xm, lw, row, side ? !right : right);
            if (b.t < a->y0 + 2) break;
            if (mark_fits(a, &b) && !mark_hits(&b, placed, n)) return b;
        }
    }
    return first;
}

int rjr_plot_rect(rjr_context *c, const rjr_plot_def *d, int rx, int ry, int rw, int rh)
{
    axis ax, ay;
    double f, fs, tick = 5.0, pad, left, right, top, bottom, maxw = 0.0, dmin, dmax;
    double x0, y0, x1, y1;           /* plot area in pixels (integers) */
    int i, nser, tx, ty, has_x, has_y;
    const rjr_rgb ink = COL_INK, grid = 0xe3e3e3, grid2 = 0xf1f1f1;
    if (!c->in_frame) { set_err(c->err, sizeof c->err, "rjr_plot_rect: no open frame"); return -1; }
    if (!d) { ctx_fail(c, "rjr_plot_rect: no definition"); return -1; }
    if ((d->logx && d->xmin < d->xmax && !(d->xmin > 0)) || (d->logy && d->ymin < d->ymax && !(d->ymin > 0))) {
        ctx_fail(c, "rjr_plot_rect: log axis range must be positive");
        return -1;
    }
    nser = d->series_count < 0 ? 0 : (d->series_count > RJR_MAX_SERIES ? RJR_MAX_SERIES : d->series_count);
    f = d->font_px > 0 ? d->font_px : floor((rw < rh ? rw : rh) * 0.03);
    if (f < 10) f = 10;
    if (f > 16 && !(d->font_px > 0)) f = 16;
    fs = floor(f * 0.85 + 0.5);
    pad = floor(f * 0.8);

    has_x = data_range(d, 0, d->logx, &dmin, &dmax);
    tx = (int)(rw / (f * 6.5));
    axis_setup(&ax, d->logx, d->xmin, d->xmax, d->xmin < d->xmax, has_x ? dmin : 0, has_x ? dmax : 1, tx < 3 ? 3 : (tx > 10 ? 10 : tx));
    has_y = data_range(d, 1, d->logy, &dmin, &dmax);
    ty = (int)(rh / (f * 4.0));
    axis_setup(&ay, d->logy, d->ymin, d->ymax, d->ymin < d->ymax, has_y ? dmin : 0, has_y ? dmax : 1, ty < 3 ? 3 : (ty > 10 ? 10 : ty));

    for (i = 0; i < ay.nmajor; i++) {
        double w = rjr_text_width(ay.label[i], fs);
        if (w > maxw) maxw = w;
    }
    left = pad + (d->ylabel ? f * 1.9 : 0.0) + maxw + tick + 4;
    right = pad + f * 1.5;
    top = pad + (d->title ? f * 2.2 : f * 0.4);
    bottom = pad + tick + 4 + fs * 1.5 + (d->xlabel ? f * 1.9 : 0.0);
    x0 = rx + floor(left); x1 = rx + rw - floor(right);
    y0 = ry + floor(top); y1 = ry + rh - floor(bottom);
    if (x1 - x0 < 20 || y1 - y0 < 20) { ctx_fail(c, "rjr_plot_rect: rectangle too small"); return -1; }

    /* grid */
    if (d->grid) {
        for (i = 0; i < ax.nminor; i++) {
            double x = floor(x0 + (ax.minor[i] - ax.lo) / (ax.hi - ax.lo) * (x1 - x0));
            rjr_rect(c, x, y0, 1, y1 - y0, grid2);
        }
        for (i = 0; i < ay.nminor; i++) {
            double y = floor(y1 - (ay.minor[i] - ay.lo) / (ay.hi - ay.lo) * (y1 - y0));
            rjr_rect(c, x0, y, x1 - x0, 1, grid2);
        }
        for (i = 0; i < ax.nmajor; i++) {
            double x = floor(x0 + (ax.major[i] - ax.lo) / (ax.hi - ax.lo) * (x1 - x0));
            rjr_rect(c, x, y0, 1, y1 - y0, grid);
        }
        for (i = 0; i < ay.nmajor; i++) {
            double y = floor(y1 - (ay.major[i] - ay.lo) / (ay.hi - ay.lo) * (y1 - y0));
            rjr_rect(c, x0, y, x1 - x0, 1, grid);
        }
    }

    /* event markers: dashed lines behind the data, labels drawn last */
    for (i = 0; i < d->marker_count && i < RJR_MAX_MARKERS; i++) {
        double xm = axis_map(&ax, d->markers[i].x, x0, x1), seg[4];
        if (!isfinite(xm) || xm < x0 || xm > x1) continue;
        seg[0] = xm; seg[1] = y0; seg[2] = xm; seg[3] = y1;
        stroke_dashed(c, seg, 2, 1.5, 0x7b52c7, 6, 4);
    }

    /* data, clipped to the plot area */
    rjr_clip(c, (int)x0, (int)y0, (int)(x1 - x0) + 1, (int)(y1 - y0) + 1);
    for (i = 0; i < nser; i++) {
        const rjr_series *s = &d->series[i];
        rjr_rgb col = (s->colour & RJR_AUTO_COLOUR) ? plot_palette[i] : s->colour;
        draw_series(c, d, s, &ax, &ay, x0, y0, x1, y1, col);
    }
    rjr_clip(c, 0, 0, 0, 0);

    /* frame, ticks, tick labels */
    rect_outline(c, x0 - 1, y0 - 1, x1 - x0 + 2, y1 - y0 + 2, 1, 0x555555);
    for (i = 0; i < ax.nminor; i++) {
        double x = floor(x0 + (ax.minor[i] - ax.lo) / (ax.hi - ax.lo) * (x1 - x0));
        rjr_rect(c, x, y1 - 3, 1, 3, ink);
    }
    for (i = 0; i < ay.nminor; i++) {
        double y = floor(y1 - (ay.minor[i] - ay.lo) / (ay.hi - ay.lo) * (y1 - y0));
        rjr_rect(c, x0, y, 3, 1, ink);
    }
    for (i = 0; i < ax.nmajor; i++) {
        double x = floor(x0 + (ax.major[i] - ax.lo) / (ax.hi - ax.lo) * (x1 - x0));
        rjr_rect(c, x, y1 - tick, 1, tick, ink);
        rjr_rect(c, x, y1 + 1, 1, 3, ink);
        rjr_text(c, x + 0.5, y1 + 4 + floor(fs * 0.5), fs, 0.0, RJR_CENTER | RJR_TOP, ink, ax.label[i]);
    }
    for (i = 0; i < ay.nmajor; i++) {
        double y = floor(y1 - (ay.major[i] - ay.lo) / (ay.hi - ay.lo) * (y1 - y0));
        rjr_rect(c, x0, y, tick, 1, ink);
        rjr_rect(c, x0 - 4, y, 3, 1, ink);
        rjr_text(c, x0 - 8, y + 0.5, fs, 0.0, RJR_RIGHT | RJR_MIDDLE, ink, ay.label[i]);
    }

    /* labels and title */
    if (d->xlabel)
        rjr_text(c, floor(0.5 * (x0 + x1)), y1 + 4 + floor(fs * 0.5) + fs + floor(f * 0.9), f, 0.0, RJR_CENTER | RJR_TOP, ink, d->xlabel);
    if (d->ylabel)
        rjr_text(c, rx + pad, floor(0.5 * (y0 + y1)), f, 90.0, RJR_CENTER | RJR_TOP, ink, d->ylabel);
    if (d->title)
        rjr_text(c, floor(0.5 * (x0 + x1)), ry + pad, floor(f * 1.15), 0.0, RJR_CENTER | RJR_TOP, ink, d->title);

    /* legend */
    if (d->legend != RJR_LEGEND_NONE) {
        int n = 0;
        double lw = 0.0, rowh = floor(fs * 1.8), sample = floor(fs * 2.4), bw, bh, bx, by;
        for (i = 0; i < nser; i++)
            if (d->series[i].label) {
                double w = rjr_text_width(d->series[i].label, fs);
                if (w > lw) lw = w;
                n++;
            }
        if (n > 0) {
            bw = floor(sample + lw + fs * 2.2);
            bh = floor(n * rowh + fs * 0.8);
            bx = (d->legend == RJR_LEGEND_TOP_LEFT || d->legend == RJR_LEGEND_BOTTOM_LEFT) ? x0 + 8 : x1 - 8 - bw;
            by = (d->legend == RJR_LEGEND_BOTTOM_LEFT || d->legend == RJR_LEGEND_BOTTOM_RIGHT) ? y1 - 8 - bh : y0 + 8;
            rjr_rect(c, bx, by, bw, bh, 0xffffff);
            rect_outline(c, bx, by, bw, bh, 1, 0xa6a6a6);
            n = 0;
            for (i = 0; i < nser; i++) {
                const rjr_series *s = &d->series[i];
                rjr_rgb col = (s->colour & RJR_AUTO_COLOUR) ? plot_palette[i] : s->colour;
                double w = s->width_px > 0 ? s->width_px : 2.0, yy, seg[4];
                if (!s->label) continue;
                yy = by + floor(fs * 0.4) + n * rowh + 0.5 * rowh;
                seg[0] = bx + floor(fs * 0.7); seg[1] = yy; seg[2] = seg[0] + sample; seg[3] = yy;
                if (!s->no_line) {
                    if (s->dashed) stroke_dashed(c, seg, 2, w, col, w * 3.5 + 3, w * 2 + 2.5);
                    else stroke(c, seg, 2, w, col, 0);
                }
                if (s->points || s->no_line) rjr_disc(c, seg[0] + 0.5 * sample, yy, w * 1.3 > 2.5 ? w * 1.3 : 2.5, col);
                rjr_text(c, seg[2] + floor(fs * 0.6), yy, fs, 0.0, RJR_LEFT | RJR_MIDDLE, ink, s->label);
                n++;
            }
        }
    }

    /* marker labels on a white backing, in rows that do not overlap (mark_place) */
    {
        mark_box placed[RJR_MAX_MARKERS];
        const mark_area area = { x0, y0, x1, y1, fs };
        int n = 0;
        for (i = 0; i < d->marker_count && i < RJR_MAX_MARKERS; i++) {
            const double xm = axis_map(&ax, d->markers[i].x, x0, x1);
            if (!isfinite(xm) || xm < x0 || xm > x1 || !d->markers[i].label) continue;
            placed[n] = mark_place(&area, xm, rjr_text_width(d->markers[i].label, fs), i % 3, placed, n);
            rjr_rect(c, placed[n].l, placed[n].t, placed[n].r - placed[n].l, placed[n].b - placed[n].t, 0xffffff);
            rjr_text(c, placed[n].l + 2, placed[n].t + 3, fs, 0.0, RJR_LEFT | RJR_TOP, 0x5a34a8, d->markers[i].label);
            n++;
        }
    }
    return c->failed ? -1 : 0;
}

int rjr_plot(rjr_context *c, const rjr_plot_def *d)
{
    int r;
    if (rjr_begin(c, 0xffffff) != 0) return -1;
    r = rjr_plot_rect(c, d, 0, 0, c->width, c->height);
    if (rjr_end(c) != 0) return -1;
    return r;
}

#endif /* RJR_PNG_ONLY */

/* ---- PNG -------------------------------------------------------------------------------- */

/* What a failed write leaves for the message: the caller's buffer, and the file, whose
   error flag tells a system error (errno: a full disk) from one of libpng's own. */
typedef struct png_errctx { char *err; size_t errlen; FILE *f; const char *path; } png_errctx;

static void png_error_cb(png_structp png, png_const_charp msg)
{
    png_errctx *e = (png_errctx *)png_get_error_ptr(png);
    const int sys = errno;
    if (e && e->err && e->errlen && e->f && ferror(e->f) && sys)
        snprintf(e->err, e->errlen, "error writing %.200s: %s", e->path, strerror(sys));
    else if (e && e->err && e->errlen)
        snprintf(e->err, e->errlen, "libpng: %s", msg);
    png_longjmp(png, 1);
}

static void png_warning_cb(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg;
}

static void png_rows(png_structp png, const unsigned char *rgb, int w, int h)
{
    int y;
    for (y = 0; y < h; y++) png_write_row(png, rgb + (size_t)y * (size_t)w * 3);
}

static int png_encode(FILE *f, const unsigned char *rgb, int w, int h, png_errctx *ec)
{
    png_structp png;
    png_infop info;
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, ec, png_error_cb, png_warning_cb);
    if (!png) return -1;
    info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        return -1;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 1);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
    png_write_info(png, info);
    png_rows(png, rgb, w, h);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    return 0;
}

/* The file a PNG goes to, opened as fopen(path, "wb") would, and whether this call
   created it (O_EXCL): a failed write may remove only such a file. What was there before
   (a device such as /dev/full, a file of someone else's) is left where it is. */
static FILE *png_open(const char *path, int *created)
{
    FILE *f;
    int e, fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0666);
    *created = fd >= 0;
    if (fd < 0 && errno == EEXIST) fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0666);
    if (fd < 0) return NULL;
    f = fdopen(fd, "wb");
    if (f) return f;
    /* the reason is fdopen's: close and unlink must not overwrite it */
    e = errno;
    close(fd);
    if (*created) unlink(path);
    errno = e;
    return NULL;
}

/* After a failed write: removes the file this call created, and only when the path still
   names that very file (same device and inode, a regular file). */
static void png_discard(const char *path, const struct stat *made)
{
    struct stat now;
    if (lstat(path, &now) != 0 || !S_ISREG(now.st_mode)) return;
    if (now.st_dev != made->st_dev || now.st_ino != made->st_ino) return;
    unlink(path);
}

int rjr_write_png(const char *path, const unsigned char *rgb, int w, int h, char *err, size_t errlen)
{
    FILE *f;
    png_errctx ec;
    struct stat made;
    int r, created;
    char m[300];
    set_err(err, errlen, "");
    if (!path || !rgb || w < 1 || h < 1) { set_err(err, errlen, "rjr_write_png: bad arguments"); return -1; }
    f = png_open(path, &created);
    if (!f) {
        snprintf(m, sizeof m, "cannot open %.200s for writing: %s", path, strerror(errno));
        set_err(err, errlen, m);
        return -1;
    }
    /* the file as created, to know it again before removing anything */
    created = created && fstat(fileno(f), &made) == 0;
    ec.err = err;
    ec.errlen = errlen;
    ec.f = f;
    ec.path = path;
    r = png_encode(f, rgb, w, h, &ec);
    if (r != 0 && err && errlen && !err[0]) set_err(err, errlen, "libpng: write failed");
    if (fclose(f) != 0 && r == 0) {
        snprintf(m, sizeof m, "error writing %.200s: %s", path, strerror(errno));
        set_err(err, errlen, m);
        r = -1;
    }
    if (r != 0 && created) png_discard(path, &made);
    return r;
}

#ifndef RJR_PNG_ONLY
int rjr_save_png(rjr_context *c, const char *path, char *err, size_t errlen)
{
    unsigned char *rgb = (unsigned char *)malloc((size_t)c->width * (size_t)c->height * 3);
    int r;
    if (!rgb) { set_err(err, errlen, "out of memory"); return -1; }
    if (rjr_read_pixels(c, rgb) != 0) {
        set_err(err, errlen, c->err);
        free(rgb);
        return -1;
    }
    r = rjr_write_png(path, rgb, c->width, c->height, err, errlen);
    free(rgb);
    return r;
}
#endif

int rjr_load_png(const char *path, unsigned char **rgb, int *w, int *h, char *err, size_t errlen)
{
    png_image img;
    png_color bg;
    unsigned char *buf;
    char m[300];
    *rgb = NULL;
    *w = *h = 0;
    set_err(err, errlen, "");
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path)) {
        snprintf(m, sizeof m, "%.200s: %s", path, img.message);
        set_err(err, errlen, m);
        return -1;
    }
    img.format = PNG_FORMAT_RGB;
    buf = (unsigned char *)malloc(PNG_IMAGE_SIZE(img));
    if (!buf) {
        png_image_free(&img);
        set_err(err, errlen, "out of memory");
        return -1;
    }
    bg.red = bg.green = bg.blue = 255;
    if (!png_image_finish_read(&img, &bg, buf, 0, NULL)) {
        snprintf(m, sizeof m, "%.200s: %s", path, img.message);
        set_err(err, errlen, m);
        png_image_free(&img);
        free(buf);
        return -1;
    }
    *rgb = buf;
    *w = (int)img.width;
    *h = (int)img.height;
    return 0;
}

/* ---- Comparison -------------------------------------------------------------------------- */

int rjr_compare(const unsigned char *a, const unsigned char *b, int w, int h, int thr, rjr_diff *out)
{
    size_t i, n = (size_t)w * (size_t)h;
    double sq = 0.0, ab = 0.0;
    int mx = 0;
    long bad = 0;
    if (!a || !b || !out || w < 1 || h < 1) return -1;
    for (i = 0; i < n; i++) {
        int dr = abs((int)a[3 * i] - (int)b[3 * i]);
        int dg = abs((int)a[3 * i + 1] - (int)b[3 * i + 1]);
        int db = abs((int)a[3 * i + 2] - (int)b[3 * i + 2]);
        int d = dr > dg ? dr : dg;
        if (db > d) d = db;
        if (d > mx) mx = d;
        if (d > thr) bad++;
        if (d) {
            sq += (double)(dr * dr + dg * dg + db * db);
            ab += (double)(dr + dg + db);
        }
    }
    out->max_delta = mx;
    out->bad_pixels = bad;
    out->mae = ab / (3.0 * (double)n);
    out->psnr = sq > 0 ? 10.0 * log10(255.0 * 255.0 / (sq / (3.0 * (double)n))) : INFINITY;
    return 0;
}

void rjr_diff_image(const unsigned char *g, const unsigned char *a, int w, int h, int thr, unsigned char *out)
{
    size_t i, n = (size_t)w * (size_t)h;
    for (i = 0; i < n; i++) {
        const unsigned char *p = g + 3 * i, *q = a + 3 * i;
        unsigned char *o = out + 3 * i;
        int dr = abs((int)p[0] - (int)q[0]), dg = abs((int)p[1] - (int)q[1]), db = abs((int)p[2] - (int)q[2]);
        int d = dr > dg ? dr : dg;
        if (db > d) d = db;
        if (d > thr) { o[0] = 255; o[1] = 0; o[2] = 0; }
        else if (d > 0) { o[0] = 255; o[1] = 170; o[2] = 0; }
        else {
            int lum = (77 * p[0] + 150 * p[1] + 29 * p[2]) >> 8;
            unsigned char v = (unsigned char)(255 - (255 - lum) / 3);
            o[0] = o[1] = o[2] = v;
        }
    }
}

int rjr_write_diff_png(const char *path, const unsigned char *golden, const unsigned char *actual, int w, int h,
                       int thr, char *err, size_t errlen)
{
    unsigned char *d = (unsigned char *)malloc((size_t)w * (size_t)h * 3);
    int r;
    if (!d) { set_err(err, errlen, "out of memory"); return -1; }
    rjr_diff_image(golden, actual, w, h, thr, d);
    r = rjr_write_png(path, d, w, h, err, errlen);
    free(d);
    return r;
}
