/* A stand-in for Mesa's swrast_dri.so, loaded only by the Xvfb we carry to the GPU machine (bench/pack_xvfb.sh).
 *
 * Why: Xvfb offers the GLX extension only when its DRISWRAST provider can load a "swrast" DRI driver and read
 * fbconfigs from it; without one, GLX is missing and no GL window opens at all. Mesa's real driver needs libLLVM,
 * z3 and ICU (about 50 MB of packages), which does not fit what we may carry. Clients that render directly (the
 * NVIDIA GLX client library selected with __GLX_VENDOR_LIBRARY_NAME=nvidia, Mesa's own GLX client) never ask the
 * server to render: from the server they need GLX itself, its fbconfigs/visuals and GLX drawables. This stub gives
 * exactly that: the RGBA8/RGBX8 configs llvmpipe reports (same attribute values, so Mesa's client matches them
 * too), dummy drawables, and no server-side (indirect) contexts.
 *
 * Built against Mesa's GL/internal/dri_interface.h (mesa-common-dev), the header the X server was built with. */
#include <stdint.h>
#include <stdlib.h>
#include <GL/internal/dri_interface.h>

enum { kAttributeCount = 53 };   /* __DRI_ATTRIB_BUFFER_SIZE (1) .. __DRI_ATTRIB_ALPHA_SHIFT (53) */

struct __DRIconfigRec {
    unsigned int values[kAttributeCount + 1];   /* indexed by __DRI_ATTRIB_* */
};
struct __DRIscreenRec { int screen; };
struct __DRIdrawableRec { int unused; };

/* Color formats x depth/stencil x buffering: 2 x 3 x 3. */
#define kConfigCount 18

static void fill_config(struct __DRIconfigRec* c, int alpha, unsigned depth, unsigned stencil, int doubled,
                        unsigned swap_method) {
    unsigned int* v = c->values;
    v[__DRI_ATTRIB_BUFFER_SIZE] = alpha ? 32 : 24;
    v[__DRI_ATTRIB_RED_SIZE] = v[__DRI_ATTRIB_GREEN_SIZE] = v[__DRI_ATTRIB_BLUE_SIZE] = 8;
    v[__DRI_ATTRIB_ALPHA_SIZE] = alpha ? 8 : 0;
    v[__DRI_ATTRIB_DEPTH_SIZE] = depth;
    v[__DRI_ATTRIB_STENCIL_SIZE] = stencil;
    v[__DRI_ATTRIB_RENDER_TYPE] = __DRI_ATTRIB_RGBA_BIT;
    v[__DRI_ATTRIB_CONFORMANT] = 1;
    v[__DRI_ATTRIB_DOUBLE_BUFFER] = doubled ? 1 : 0;
    v[__DRI_ATTRIB_TRANSPARENT_TYPE] = 0x8000;   /* GLX_NONE */
    v[__DRI_ATTRIB_TRANSPARENT_INDEX_VALUE] = 0x8000;
    v[__DRI_ATTRIB_TRANSPARENT_RED_VALUE] = v[__DRI_ATTRIB_TRANSPARENT_GREEN_VALUE] = 0xffffffffu;   /* DONT_CARE */
    v[__DRI_ATTRIB_TRANSPARENT_BLUE_VALUE] = v[__DRI_ATTRIB_TRANSPARENT_ALPHA_VALUE] = 0xffffffffu;
    /* B8G8R8(A8) in a 32-bit word: the masks of Xvfb's depth-24 TrueColor visual, which the server pairs by mask. */
    v[__DRI_ATTRIB_RED_MASK] = 0x00ff0000u;
    v[__DRI_ATTRIB_GREEN_MASK] = 0x0000ff00u;
    v[__DRI_ATTRIB_BLUE_MASK] = 0x000000ffu;
    v[__DRI_ATTRIB_ALPHA_MASK] = alpha ? 0xff000000u : 0;
    v[__DRI_ATTRIB_SWAP_METHOD] = swap_method;
    v[__DRI_ATTRIB_MAX_SWAP_INTERVAL] = 0x7fffffff;
    v[__DRI_ATTRIB_BIND_TO_TEXTURE_RGB] = v[__DRI_ATTRIB_BIND_TO_TEXTURE_RGBA] = 1;
    v[__DRI_ATTRIB_BIND_TO_TEXTURE_TARGETS] =
        __DRI_ATTRIB_TEXTURE_1D_BIT | __DRI_ATTRIB_TEXTURE_2D_BIT | __DRI_ATTRIB_TEXTURE_RECTANGLE_BIT;
    v[__DRI_ATTRIB_YINVERTED] = 1;
    v[__DRI_ATTRIB_RED_SHIFT] = 16;
    v[__DRI_ATTRIB_GREEN_SHIFT] = 8;
    v[__DRI_ATTRIB_BLUE_SHIFT] = 0;
    v[__DRI_ATTRIB_ALPHA_SHIFT] = alpha ? 24 : 0xffffffffu;
}

static void free_configs(const __DRIconfig** list) {
    if (!list) return;
    for (int i = 0; list[i]; ++i) free((void*)list[i]);
    free(list);
}

/* The server owns what this returns: it frees every config and then the list when the screen goes away, so
 * each is its own heap block. NULL when out of memory. */
static const __DRIconfig** build_configs(void) {
    static const unsigned depth_stencil[3][2] = {{0, 0}, {24, 0}, {24, 8}};
    /* single-buffered; double-buffered with undefined and with copy swaps (as llvmpipe lists them) */
    static const struct { int doubled; unsigned swap; } buffering[3] = {{0, 0x8063}, {1, 0x8063}, {1, 0x8062}};
    const __DRIconfig** list = calloc(kConfigCount + 1, sizeof *list);
    if (!list) return NULL;
    int n = 0;
    for (int alpha = 1; alpha >= 0; --alpha)
        for (int ds = 0; ds < 3; ++ds)
            for (int b = 0; b < 3; ++b) {
                struct __DRIconfigRec* config = calloc(1, sizeof *config);
                if (!config) {
                    free_configs(list);
                    return NULL;
                }
                fill_config(config, alpha, depth_stencil[ds][0], depth_stencil[ds][1], buffering[b].doubled,
                            buffering[b].swap);
                list[n++] = config;
            }
    return list;
}

static int get_config_attrib(const __DRIconfig* config, unsigned int attrib, unsigned int* value) {
    if (attrib < 1 || attrib > kAttributeCount) return 0;
    *value = config->values[attrib];
    return 1;
}

static int index_config_attrib(const __DRIconfig* config, int index, unsigned int* attrib, unsigned int* value) {
    if (index < 0 || index >= kAttributeCount) return 0;
    *attrib = (unsigned int)index + 1;
    *value = config->values[index + 1];
    return 1;
}

static __DRIscreen* new_screen(int screen, const __DRIconfig*** driver_configs) {
    __DRIscreen* s = calloc(1, sizeof *s);
    const __DRIconfig** configs = build_configs();
    if (!s || !configs) {
        free(s);
        free_configs(configs);
        return NULL;
    }
    s->screen = screen;
    *driver_configs = configs;
    return s;
}

static __DRIscreen* swrast_create_screen(int screen, const __DRIextension** loader, const __DRIconfig*** configs,
                                         void* loader_private) {
    (void)loader;
    (void)loader_private;
    return new_screen(screen, configs);
}

static __DRIscreen* swrast_create_screen2(int screen, const __DRIextension** loader, const __DRIextension** driver,
                                          const __DRIconfig*** configs, void* loader_private) {
    (void)driver;
    return swrast_create_screen(screen, loader, configs, loader_private);
}

static __DRIscreen* core_create_screen(int screen, int fd, unsigned int sarea, const __DRIextension** extensions,
                                       const __DRIconfig*** configs, void* loader_private) {
    (void)screen, (void)fd, (void)sarea, (void)extensions, (void)configs, (void)loader_private;
    return NULL;   /* DRI1: never used by Xvfb */
}

static void destroy_screen(__DRIscreen* screen) { free(screen); }

static const __DRIextension* no_screen_extensions[] = {NULL};
static const __DRIextension** get_extensions(__DRIscreen* screen) {
    (void)screen;
    return no_screen_extensions;
}

/* GLX drawables exist on the server (glXCreateWindow); direct-rendering clients draw into them themselves. */
static __DRIdrawable* swrast_create_drawable(__DRIscreen* screen, const __DRIconfig* config, void* loader_private) {
    (void)screen, (void)config, (void)loader_private;
    return calloc(1, sizeof(__DRIdrawable));
}

static __DRIdrawable* core_create_drawable(__DRIscreen* screen, const __DRIconfig* config, unsigned int id,
                                           unsigned int head, void* loader_private) {
    (void)id, (void)head;
    return swrast_create_drawable(screen, config, loader_private);
}

static void destroy_drawable(__DRIdrawable* drawable) { free(drawable); }
static void swap_buffers(__DRIdrawable* drawable) { (void)drawable; }

/* No indirect rendering: the server cannot draw. A client asking for it gets a context that never binds. */
static __DRIcontext* core_create_context(__DRIscreen* screen, const __DRIconfig* config, __DRIcontext* shared,
                                         void* loader_private) {
    (void)screen, (void)config, (void)shared, (void)loader_private;
    return NULL;
}
static __DRIcontext* create_context_for_api(__DRIscreen* screen, int api, const __DRIconfig* config,
                                            __DRIcontext* shared, void* data) {
    (void)api;
    return core_create_context(screen, config, shared, data);
}
static __DRIcontext* create_context_attribs(__DRIscreen* screen, int api, const __DRIconfig* config,
                                            __DRIcontext* shared, unsigned num_attribs, const uint32_t* attribs,
                                            unsigned* error, void* loader_private) {
    (void)screen, (void)api, (void)config, (void)shared, (void)num_attribs, (void)attribs, (void)loader_private;
    if (error) *error = __DRI_CTX_ERROR_BAD_API;
    return NULL;
}
static int copy_context(__DRIcontext* dst, __DRIcontext* src, unsigned long mask) {
    (void)dst, (void)src, (void)mask;
    return 0;
}
static void destroy_context(__DRIcontext* context) { (void)context; }
static int bind_context(__DRIcontext* context, __DRIdrawable* draw, __DRIdrawable* read) {
    (void)context, (void)draw, (void)read;
    return 0;
}
static int unbind_context(__DRIcontext* context) {
    (void)context;
    return 1;
}

static const __DRIcoreExtension core = {
    {__DRI_CORE, 2},   core_create_screen, destroy_screen,   get_extensions,
    get_config_attrib, index_config_attrib, core_create_drawable, destroy_drawable,
    swap_buffers,      core_create_context, copy_context,      destroy_context,
    bind_context,      unbind_context,
};

/* Version 4: the server then also offers GLX_ARB_create_context(_profile), which core-profile clients look for. */
static const __DRIswrastExtension swrast = {
    {__DRI_SWRAST, 4}, swrast_create_screen,  swrast_create_drawable,
    create_context_for_api, create_context_attribs, swrast_create_screen2,
};

static const __DRIextension* driver_extensions[] = {&core.base, &swrast.base, NULL};

__attribute__((visibility("default"))) const __DRIextension** __driDriverGetExtensions_swrast(void) {
    return driver_extensions;
}
