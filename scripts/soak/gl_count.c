// LD_PRELOAD shim for scripts/soak.sh: counts the GL object names a process
// holds. Ripple resolves every GL entry point through eglGetProcAddress
// (render/gl.cc), so the shim wraps that: for the glGen*/glDelete* pairs and
// glCreateProgram/glCreateShader with their deletes it hands back counting
// wrappers. Each time the number of live names reaches a new peak, and at
// exit, it appends "<seconds since start> <live> <created> <deleted>" to
// $RIPPLE_GL_COUNT_FILE. A leak of GL objects per frame shows as peaks that
// keep coming late in the run and names still live at exit.
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void (*GenFn)(int, unsigned*);
typedef void (*DelFn)(int, const unsigned*);
typedef unsigned (*CreateFn)(unsigned);
typedef unsigned (*CreateProgramFn)(void);
typedef void (*DelOneFn)(unsigned);
typedef void* (*ProcFn)(const char*);

static long live, peak, created, deleted;
static double start_s;

static double Now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

static void Log(void) {
  const char* path = getenv("RIPPLE_GL_COUNT_FILE");
  if (!path) return;
  FILE* f = fopen(path, "a");
  if (!f) return;
  fprintf(f, "%.1f %ld %ld %ld\n", Now() - start_s, live, created, deleted);
  fclose(f);
}

static void Add(long n) {
  live += n;
  created += n;
  if (live > peak) {
    peak = live;
    Log();
  }
}

static void Remove(int n, const unsigned* names) {
  for (int i = 0; i < n; ++i) {
    if (names[i] != 0) {
      --live;
      ++deleted;
    }
  }
}

__attribute__((constructor)) static void Start(void) { start_s = Now(); }
__attribute__((destructor)) static void Stop(void) { Log(); }

// One wrapper pair per object kind; the real entry point is kept per kind.
#define GEN_PAIR(kind)                                   \
  static GenFn real_gen_##kind;                          \
  static DelFn real_del_##kind;                          \
  static void Gen_##kind(int n, unsigned* names) {       \
    real_gen_##kind(n, names);                           \
    Add(n);                                              \
  }                                                      \
  static void Del_##kind(int n, const unsigned* names) { \
    Remove(n, names);                                    \
    real_del_##kind(n, names);                           \
  }
GEN_PAIR(Textures)
GEN_PAIR(Buffers)
GEN_PAIR(Framebuffers)
GEN_PAIR(Renderbuffers)
GEN_PAIR(VertexArrays)
GEN_PAIR(Queries)

static CreateProgramFn real_create_program;
static DelOneFn real_delete_program;
static CreateFn real_create_shader;
static DelOneFn real_delete_shader;
static unsigned CreateProgram(void) {
  unsigned id = real_create_program();
  if (id) Add(1);
  return id;
}
static void DeleteProgram(unsigned id) {
  Remove(1, &id);
  real_delete_program(id);
}
static unsigned CreateShader(unsigned type) {
  unsigned id = real_create_shader(type);
  if (id) Add(1);
  return id;
}
static void DeleteShader(unsigned id) {
  Remove(1, &id);
  real_delete_shader(id);
}

void* eglGetProcAddress(const char* name) {
  static ProcFn real;
  if (!real) real = (ProcFn)dlsym(RTLD_NEXT, "eglGetProcAddress");
  void* p = real(name);
  if (!p || !name) return p;
#define WRAP(kind)                       \
  if (!strcmp(name, "glGen" #kind)) {    \
    real_gen_##kind = (GenFn)p;          \
    return (void*)Gen_##kind;            \
  }                                      \
  if (!strcmp(name, "glDelete" #kind)) { \
    real_del_##kind = (DelFn)p;          \
    return (void*)Del_##kind;            \
  }
  WRAP(Textures)
  WRAP(Buffers)
  WRAP(Framebuffers)
  WRAP(Renderbuffers)
  WRAP(VertexArrays)
  WRAP(Queries)
  if (!strcmp(name, "glCreateProgram")) {
    real_create_program = (CreateProgramFn)p;
    return (void*)CreateProgram;
  }
  if (!strcmp(name, "glDeleteProgram")) {
    real_delete_program = (DelOneFn)p;
    return (void*)DeleteProgram;
  }
  if (!strcmp(name, "glCreateShader")) {
    real_create_shader = (CreateFn)p;
    return (void*)CreateShader;
  }
  if (!strcmp(name, "glDeleteShader")) {
    real_delete_shader = (DelOneFn)p;
    return (void*)DeleteShader;
  }
  return p;
}
