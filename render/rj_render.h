/* rj_render.h - off-screen renderer for revjoint.h: mechanism frames, plots, PNG I/O and
   golden-image comparison. OpenGL through OSMesa (default) or EGL surfaceless
   (compile rj_render.c with -DRJ_RENDER_EGL), 4x MSAA, deterministic output.

   Build:  cc -std=c99 -c rj_render.c $(pkg-config --cflags osmesa libpng)
           link with $(pkg-config --libs libpng) -lm -ldl -lpthread (the last two only
           matter before glibc 2.34). OSMesa is not linked: the first rjr_create opens
           libOSMesa.so.8 with dlopen (RJ_OSMESA=FILE opens FILE instead), so a program
           that does not draw never loads it.
           (EGL: -DRJ_RENDER_EGL, $(pkg-config --libs egl opengl libpng) -lm; linked)
   The program must also compile the revjoint.h implementation in one translation unit.

   Conventions
   - Pixel coordinates: origin at the top-left corner, x right, y down, in pixels; pixel
     (i, j) covers [i, i+1) x [j, j+1).
   - Colours: 0xRRGGBB. Images: 8-bit RGB, rows top-down, no padding (w * 3 bytes a row).
   - Functions returning int return 0 on success and -1 on failure; the message is then in
     rjr_error(ctx) or in the caller's err buffer. Nothing is ever printed.
   - A context is used by one thread at a time; several contexts may exist (one per size,
     or rjr_resize one context). The context is made current by the calls that need it.
*/
#ifndef RJ_RENDER_H
#define RJ_RENDER_H

#include <stddef.h>
#include <stdint.h>
#include "../revjoint.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef uint32_t rjr_rgb;              /* 0xRRGGBB */
#define RJR_AUTO_COLOUR 0xFF000000u    /* series colour: take the next palette colour */

typedef struct rjr_context rjr_context;

/* ---- Context ---------------------------------------------------------------------- */

/* Creates an off-screen GL context with a width x height 8-bit RGB target (4x MSAA when
   the driver has it). Returns NULL and fills err on failure. */
rjr_context *rjr_create(int width, int height, char *err, size_t errlen);
/* Loads the GL library (OSMesa) if that has not been done: 0 when the renderer can start,
   -1 with err naming the library that could not be loaded and how to install it.
   rjr_create calls it; a program may call it before a long run to fail early. */
int rjr_available(char *err, size_t errlen);
void rjr_destroy(rjr_context *ctx);
/* Changes the target size (contents are lost). */
int rjr_resize(rjr_context *ctx, int width, int height);
int rjr_width(const rjr_context *ctx);
int rjr_height(const rjr_context *ctx);
int rjr_samples(const rjr_context *ctx);           /* MSAA samples in use (1 = none) */
const char *rjr_gl_renderer(const rjr_context *ctx); /* GL_RENDERER, e.g. "llvmpipe (...)" */
const char *rjr_gl_version(const rjr_context *ctx);  /* GL_VERSION */
const char *rjr_backend(const rjr_context *ctx);     /* "osmesa" or "egl-surfaceless" */
const char *rjr_error(const rjr_context *ctx);       /* last error message ("" if none) */

/* ---- Frames and primitives (pixel coordinates) ------------------------------------- */

/* A frame: rjr_begin clears to bg; draw; rjr_end resolves the MSAA buffer. The pixels can
   then be read with rjr_read_pixels / rjr_save_png any number of times.
   rjr_draw_state and rjr_plot do begin/end themselves. */
int rjr_begin(rjr_context *ctx, rjr_rgb bg);
int rjr_end(rjr_context *ctx);

/* Text alignment: one horizontal flag | one vertical flag. */
#define RJR_LEFT     0
#define RJR_CENTER   1
#define RJR_RIGHT    2
#define RJR_BASELINE 0
#define RJR_TOP      4   /* (x, y) is at the top of the capitals */
#define RJR_MIDDLE   8   /* half the capital height */
#define RJR_BOTTOM   12  /* bottom of the descenders */

void rjr_rect(rjr_context *ctx, double x, double y, double w, double h, rjr_rgb c);
void rjr_line(rjr_context *ctx, double x0, double y0, double x1, double y1, double width, rjr_rgb c); /* round caps */
/* Polyline through n points xy[2n]; dashed != 0 gives dashes of about 4 line widths. */
void rjr_polyline(rjr_context *ctx, const double *xy, int n, double width, rjr_rgb c, int dashed);
void rjr_disc(rjr_context *ctx, double x, double y, double r, rjr_rgb c);
/* Stroke font: digits, A-Z, a-z and . , - + = ( ) / : % [ ] _ ' * < > ! ? # space.
   size_px is the capital height; angle_deg rotates counter-clockwise about (x, y).
   Returns the advance width in pixels. Unknown characters are drawn as a small box. */
double rjr_text(rjr_context *ctx, double x, double y, double size_px, double angle_deg,
                int align, rjr_rgb c, const char *s);
double rjr_text_width(const char *s, double size_px);
/* Restricts drawing to a pixel rectangle (w or h <= 0: whole target). */
void rjr_clip(rjr_context *ctx, int x, int y, int w, int h);

/* ---- Mechanism frames ------------------------------------------------------------- */

typedef struct rjr_view {
    double cx, cy;             /* m: world point at the image centre */
    double mpp;                /* metres per pixel, > 0 */
    double thickness_factor;   /* drawn link thickness = max(height * factor / mpp, min) px */
    double min_thickness_px;
    int show_time;             /* "t = ... s" in the top-left corner */
    int show_scale;            /* scale bar in the bottom-left corner */
    int show_limits;           /* joint limit arcs and angle needles */
    int show_ground;           /* ground hatching at ground pins and fixed/clamped roots */
    int show_nodes;            /* small dots at the nodes */
    const char *caption;       /* optional text in the top-right corner (NULL: none) */
    double font_px;            /* text size (capital height); 0 = automatic */
    rjr_rgb background;        /* default white */
    /* Aids for frames read without the source; all off (0 / NULL) by default. */
    int show_legend;           /* a key to the joint colours (free, at a limit, locked) in the corner
                                  that covers the fewest link pixels */
    const char *const *joint_names; /* one name per joint drawn beside it (NULL: none; a NULL entry:
                                  that joint has none) */
    int show_joint_angles;     /* each joint's running angle (rj_joint_theta_running) in degrees
                                  beside it, after its name */
    int text_band;             /* a band at the top for the time stamp and caption: the view is drawn
                                  scaled about the top centre into the area below it, so no link
                                  reaches the texts (rjr_world_to_pixel follows) */
    int separate_stacked;      /* links lying on one another (stowed panels) are drawn side by side,
                                  and every link, thin ones too, as a fill with a dark outline */
} rjr_view;

/* Defaults: centre (0, 0), 0.005 m/px, factor 1, min 3 px, time, scale, limits, ground on;
   legend, joint labels, text band and stack separation off. */
rjr_view rjr_view_default(void);
/* World bounding box {xmin, ymin, xmax, ymax} of a state (nodes, joints, ground pins);
   rjr_bbox_init makes an empty box, rjr_bbox_add grows it (for whole animations). */
void rjr_bbox_init(double box[4]);
void rjr_bbox_add(double box[4], const rj_model *m, const rj_state *s);
/* Sets cx, cy, mpp so the box fits a width x height image with margin_px on every side.
   Fix the view once for an animation so frames do not jump. */
int rjr_view_fit_box(rjr_view *v, const double box[4], int width, int height, double margin_px);
int rjr_view_fit(rjr_view *v, const rj_model *m, const rj_state *s, int width, int height, double margin_px);
/* World (m) to pixel coordinates under a view, for overlays. */
void rjr_world_to_pixel(const rjr_context *ctx, const rjr_view *v, double x, double y, double *px, double *py);

/* One complete frame (begin + scene + end). */
int rjr_draw_state(rjr_context *ctx, const rj_model *m, const rj_state *s, const rjr_view *view);
/* The scene only, into an open frame (no clear), e.g. to add overlays. */
int rjr_draw_scene(rjr_context *ctx, const rj_model *m, const rj_state *s, const rjr_view *view);

/* ---- Plots ------------------------------------------------------------------------ */

#define RJR_MAX_SERIES  8
#define RJR_MAX_MARKERS 16
enum { RJR_LEGEND_TOP_RIGHT = 0, RJR_LEGEND_TOP_LEFT, RJR_LEGEND_BOTTOM_RIGHT,
       RJR_LEGEND_BOTTOM_LEFT, RJR_LEGEND_NONE };

typedef struct rjr_series {
    const double *x, *y;       /* n samples; non-finite (and, on log axes, <= 0) values break the line */
    int n;
    const char *label;         /* legend text, NULL = not in the legend */
    rjr_rgb colour;            /* RJR_AUTO_COLOUR = palette */
    int dashed;
    int points;                /* also draw a dot at every sample */
    int no_line;               /* points only */
    double width_px;           /* 0 = 2 px */
} rjr_series;

typedef struct rjr_marker {    /* vertical event line at x with a short label ("lock 2") */
    double x;
    const char *label;
} rjr_marker;

typedef struct rjr_plot_def {
    const char *title, *xlabel, *ylabel;   /* NULL = none */
    int logx, logy;
    double xmin, xmax, ymin, ymax;         /* used when min < max, else automatic */
    int series_count;
    rjr_series series[RJR_MAX_SERIES];
    int marker_count;
    rjr_marker markers[RJR_MAX_MARKERS];
    int legend;                            /* RJR_LEGEND_* */
    int grid;                              /* light grid at the major ticks */
    double font_px;                        /* 0 = automatic */
} rjr_plot_def;

/* Zeroed definition with grid on, legend top-right and automatic colours. */
rjr_plot_def rjr_plot_default(void);
/* One complete frame with a white background. */
int rjr_plot(rjr_context *ctx, const rjr_plot_def *def);
/* A plot into the pixel rectangle (x, y, w, h) of an open frame. */
int rjr_plot_rect(rjr_context *ctx, const rjr_plot_def *def, int x, int y, int w, int h);

/* ---- Pixels and PNG --------------------------------------------------------------- */

/* Copies the last frame to rgb (width * height * 3 bytes, top-down). */
int rjr_read_pixels(rjr_context *ctx, unsigned char *rgb);
/* Writes an 8-bit RGB PNG (zlib level 1, filter NONE, no time/text chunks). */
int rjr_write_png(const char *path, const unsigned char *rgb, int w, int h, char *err, size_t errlen);
/* rjr_read_pixels + rjr_write_png. */
int rjr_save_png(rjr_context *ctx, const char *path, char *err, size_t errlen);
/* Decodes any PNG to 8-bit RGB (alpha composited on white); *rgb is malloc'ed, caller frees. */
int rjr_load_png(const char *path, unsigned char **rgb, int *w, int *h, char *err, size_t errlen);

/* ---- Comparison ------------------------------------------------------------------- */

typedef struct rjr_diff {
    int max_delta;             /* largest |a - b| over all pixels and channels */
    long bad_pixels;           /* pixels whose largest RGB delta exceeds the threshold */
    double psnr;               /* dB over RGB; INFINITY when identical */
    double mae;                /* mean absolute channel difference */
} rjr_diff;

int rjr_compare(const unsigned char *a, const unsigned char *b, int w, int h, int pixel_threshold, rjr_diff *out);
/* Difference image: light grey copy of golden; pixels with delta > threshold red, other
   changed pixels orange. out is w * h * 3 bytes. */
void rjr_diff_image(const unsigned char *golden, const unsigned char *actual, int w, int h,
                    int pixel_threshold, unsigned char *out);
int rjr_write_diff_png(const char *path, const unsigned char *golden, const unsigned char *actual,
                       int w, int h, int pixel_threshold, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif /* RJ_RENDER_H */
