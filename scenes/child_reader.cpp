#include "scenes/child_reader.h"

#include <fcntl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "common/error.h"

namespace mopad::scenes {
namespace {

// --- the child's answer: a Scene as bytes (the same process image on both sides) ---

class Writer {
 public:
  void U32(std::uint32_t v) { Raw(&v, sizeof v); }
  void I32(std::int32_t v) { Raw(&v, sizeof v); }
  void F32(float v) { Raw(&v, sizeof v); }
  void Str(const std::string& s) {
    U32(static_cast<std::uint32_t>(s.size()));
    Raw(s.data(), s.size());
  }
  template <class T>
  void Vec(const std::vector<T>& v) {
    U32(static_cast<std::uint32_t>(v.size()));
    Raw(v.data(), v.size() * sizeof(T));
  }
  void Raw(const void* p, std::size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b) {}
  std::uint32_t U32() { return Get<std::uint32_t>(); }
  std::int32_t I32() { return Get<std::int32_t>(); }
  float F32() { return Get<float>(); }
  std::string Str() {
    const std::uint32_t n = U32();
    Need(n);
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  template <class T>
  void Vec(std::vector<T>* v) {
    const std::uint32_t n = U32();
    Need(static_cast<std::size_t>(n) * sizeof(T));
    v->resize(n);
    Raw(v->data(), v->size() * sizeof(T));
  }
  void Raw(void* p, std::size_t n) {
    Need(n);
    if (n) std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  bool AtEnd() const { return pos_ == b_.size(); }

 private:
  template <class T>
  T Get() {
    T v{};
    Raw(&v, sizeof v);
    return v;
  }
  void Need(std::size_t n) const {
    if (n > b_.size() - pos_) throw std::runtime_error("truncated answer of the reader");
  }
  const std::string& b_;
  std::size_t pos_ = 0;
};

void Serialise(const Scene& s, Writer* w) {
  w->Str(s.source);
  w->U32(static_cast<std::uint32_t>(s.textures.size()));
  for (const Texture& t : s.textures) {
    w->Str(t.name);
    w->I32(t.width);
    w->I32(t.height);
    w->Vec(t.rgba);
    w->U32(t.repeat ? 1 : 0);
  }
  w->U32(static_cast<std::uint32_t>(s.materials.size()));
  for (const Material& m : s.materials) {
    w->Str(m.name);
    for (int k = 0; k < 4; ++k) w->F32(m.base_color[k]);
    w->I32(m.base_color_texture);
    w->F32(m.metallic);
    w->F32(m.roughness);
    w->F32(m.transmission);
    w->F32(m.nir_reflectance);
    w->U32(m.double_sided ? 1 : 0);
  }
  w->U32(static_cast<std::uint32_t>(s.parts.size()));
  for (const MeshPart& p : s.parts) {
    w->Str(p.name);
    w->Str(p.element_id);
    w->I32(static_cast<std::int32_t>(p.element_class));
    w->Str(p.subclass);
    w->Str(p.room);
    w->I32(p.material);
    w->Vec(p.positions);
    w->Vec(p.uvs);
    w->Vec(p.triangles);
  }
}

Scene Deserialise(const std::string& bytes) {
  Reader r(bytes);
  Scene s;
  s.source = r.Str();
  s.textures.resize(r.U32());
  for (Texture& t : s.textures) {
    t.name = r.Str();
    t.width = r.I32();
    t.height = r.I32();
    r.Vec(&t.rgba);
    t.repeat = r.U32() != 0;
  }
  s.materials.resize(r.U32());
  for (Material& m : s.materials) {
    m.name = r.Str();
    for (int k = 0; k < 4; ++k) m.base_color[k] = r.F32();
    m.base_color_texture = r.I32();
    m.metallic = r.F32();
    m.roughness = r.F32();
    m.transmission = r.F32();
    m.nir_reflectance = r.F32();
    m.double_sided = r.U32() != 0;
  }
  s.parts.resize(r.U32());
  for (MeshPart& p : s.parts) {
    p.name = r.Str();
    p.element_id = r.Str();
    p.element_class = static_cast<ElementClass>(r.I32());
    p.subclass = r.Str();
    p.room = r.Str();
    p.material = r.I32();
    r.Vec(&p.positions);
    r.Vec(&p.uvs);
    r.Vec(&p.triangles);
  }
  if (!r.AtEnd()) throw std::runtime_error("trailing bytes in the answer of the reader");
  return s;
}

std::string SignalName(int sig) {
  const char* name = strsignal(sig);
  return "signal " + std::to_string(sig) + (name ? std::string(" (") + name + ")" : "");
}

// The child's exit codes: 0 a scene follows, 2 an InputError's message follows, 3 another
// exception's message follows.
constexpr int kInputError = 2, kOtherError = 3;

// The signals a crashing reader dies of.
constexpr int kCrashSignals[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};

}  // namespace

Scene ReadSceneInChild(const std::string& path, const std::string& reader,
                       const std::string& expected, const std::function<Scene()>& read_scene) {
  int fds[2];
  if (pipe(fds) != 0)
    throw InputError(path, "cannot start " + reader, std::strerror(errno), "a pipe");
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw InputError(path, "cannot start " + reader, std::strerror(errno), "a process");
  }
  if (pid == 0) {
    // The child: a crash of the reader must end it by the signal itself, which the parent names.
    // A handler the process inherited (AddressSanitizer's, libFuzzer's) would turn the signal
    // into its own report and exit code, and a contained crash into a finding.
    for (const int sig : kCrashSignals) std::signal(sig, SIG_DFL);
    // Readers print progress to stdout; the parent's stdout is not theirs to use.
    close(fds[0]);
    const int null = open("/dev/null", O_WRONLY);
    if (null >= 0) {
      dup2(null, STDOUT_FILENO);
      dup2(null, STDERR_FILENO);
    }
    Writer w;
    int code = 0;
    try {
      Serialise(read_scene(), &w);
    } catch (const InputError& e) {
      w = Writer();
      w.Str(e.what());
      code = kInputError;
    } catch (const std::exception& e) {
      w = Writer();
      w.Str(e.what());
      code = kOtherError;
    } catch (...) {
      w = Writer();
      w.Str("unknown exception");
      code = kOtherError;
    }
    const std::string& b = w.bytes();
    for (std::size_t done = 0; done < b.size();) {
      const ssize_t n = ::write(fds[1], b.data() + done, b.size() - done);
      if (n <= 0) _exit(4);
      done += static_cast<std::size_t>(n);
    }
    close(fds[1]);
    _exit(code);
  }
  close(fds[1]);
  std::string bytes;
  char buf[65536];
  for (;;) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      bytes.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status))
    throw InputError(path, reader + " crashed on this file", SignalName(WTERMSIG(status)),
                     expected);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::string why = "exit status " + std::to_string(WEXITSTATUS(status));
    if (WIFEXITED(status) &&
        (WEXITSTATUS(status) == kInputError || WEXITSTATUS(status) == kOtherError)) {
      try {
        why = Reader(bytes).Str();
      } catch (const std::exception&) {
      }
      if (WEXITSTATUS(status) == kInputError) throw InputError(why);
    }
    throw InputError(path, reader + " cannot read the file", why, expected);
  }
  try {
    return Deserialise(bytes);
  } catch (const std::exception& e) {
    throw InputError(path, reader + " gave no usable answer", e.what(), "a complete scene");
  }
}

}  // namespace mopad::scenes
