// Checkpoints as .npz: a ZIP archive (stored, ZIP64 records throughout, so any size) of .npy
// members written and read here, with nothing but the C++ library.
#include "lava/checkpoint.h"

#include <array>
#include <atomic>
#include <cctype>
#include <initializer_list>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>

#include "common/files.h"
#include "common/hash.h"
#include "common/npy.h"
#include "lava/error.h"
#include "tools/fuzzing.h"

namespace lava {
namespace {

// -- bytes --------------------------------------------------------------------------------

std::atomic<bool> compareSums{true};  // tools/fuzzing.h

uint32_t crc32(const std::string& data) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t i = 0; i < 256; ++i) {
      uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : data) c = table[(c ^ b) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}


template <typename T>
void put(std::string& out, T value) {  // little-endian, as every field of both formats
  for (size_t i = 0; i < sizeof(T); ++i) out.push_back(char((uint64_t(value) >> (8 * i)) & 0xFF));
}

template <typename T>
std::string bytesOf(const T* data, size_t count) {
  return std::string(reinterpret_cast<const char*>(data), count * sizeof(T));
}

// -- .npy ---------------------------------------------------------------------------------

std::string shapeOf(uint64_t n) {
  return "(" + std::to_string(n) + ",)";
}
std::string shapeOf(uint64_t n, uint64_t m) {
  return "(" + std::to_string(n) + ", " + std::to_string(m) + ")";
}

const std::string kClockDescr = "[('accumulator', '<f8'), ('serial', '<u8'), ('head', '<u4')]";

std::string clockData(const State& state) {
  std::string out;
  for (const EmitterClock& c : state.clocks) {
    uint64_t bits;
    std::memcpy(&bits, &c.accumulator, 8);
    put<uint64_t>(out, bits);
    put<uint64_t>(out, c.serial);
    put<uint32_t>(out, c.head);
  }
  return out;
}

// -- ZIP (stored, ZIP64) ----------------------------------------------------------------

constexpr uint32_t kLocalSignature = 0x04034b50, kCentralSignature = 0x02014b50,
                   kEndSignature = 0x06054b50, kEnd64Signature = 0x06064b50,
                   kLocatorSignature = 0x07064b50;
constexpr uint16_t kZip64Extra = 0x0001, kVersion = 45;  // 4.5: ZIP64

struct Member {
  std::string name;  // "state.npy"
  std::string data;
};

// A member's local header (sizes in its ZIP64 extra field) followed by its data.
void putLocal(std::string& out, const Member& m, uint32_t crc) {
  const uint64_t size = m.data.size();
  put<uint32_t>(out, kLocalSignature);
  put<uint16_t>(out, kVersion);
  put<uint16_t>(out, 0);  // flags
  put<uint16_t>(out, 0);  // stored
  put<uint16_t>(out, 0);  // time
  put<uint16_t>(out, 0x21);  // date: 1980-01-01
  put<uint32_t>(out, crc);
  put<uint32_t>(out, 0xFFFFFFFFu);  // sizes in the ZIP64 extra field
  put<uint32_t>(out, 0xFFFFFFFFu);
  put<uint16_t>(out, static_cast<uint16_t>(m.name.size()));
  put<uint16_t>(out, 20);  // extra: id, size, two 8-byte sizes
  out += m.name;
  put<uint16_t>(out, kZip64Extra);
  put<uint16_t>(out, 16);
  put<uint64_t>(out, size);
  put<uint64_t>(out, size);
  out += m.data;
}

// A member's central directory entry, pointing at its local header at `offset`.
void putCentral(std::string& central, const Member& m, uint32_t crc, uint64_t offset) {
  const uint64_t size = m.data.size();
  put<uint32_t>(central, kCentralSignature);
  put<uint16_t>(central, kVersion);  // made by
  put<uint16_t>(central, kVersion);  // needed
  put<uint16_t>(central, 0);
  put<uint16_t>(central, 0);
  put<uint16_t>(central, 0);
  put<uint16_t>(central, 0x21);
  put<uint32_t>(central, crc);
  put<uint32_t>(central, 0xFFFFFFFFu);
  put<uint32_t>(central, 0xFFFFFFFFu);
  put<uint16_t>(central, static_cast<uint16_t>(m.name.size()));
  put<uint16_t>(central, 28);  // extra: id, size, sizes and the local header's offset
  put<uint16_t>(central, 0);   // comment
  put<uint16_t>(central, 0);   // disk
  put<uint16_t>(central, 0);   // internal attributes
  put<uint32_t>(central, 0);   // external attributes
  put<uint32_t>(central, 0xFFFFFFFFu);  // offset in the extra field
  central += m.name;
  put<uint16_t>(central, kZip64Extra);
  put<uint16_t>(central, 24);
  put<uint64_t>(central, size);
  put<uint64_t>(central, size);
  put<uint64_t>(central, offset);
}

// The ZIP64 end record, its locator and the classic end record (every field in the ZIP64 one).
void putEnd(std::string& out, uint64_t count, uint64_t centralSize, uint64_t centralOffset) {
  const uint64_t end64Offset = out.size();
  put<uint32_t>(out, kEnd64Signature);
  put<uint64_t>(out, 44);  // the record's size after this field
  put<uint16_t>(out, kVersion);
  put<uint16_t>(out, kVersion);
  put<uint32_t>(out, 0);  // this disk
  put<uint32_t>(out, 0);  // the central directory's disk
  put<uint64_t>(out, count);
  put<uint64_t>(out, count);
  put<uint64_t>(out, centralSize);
  put<uint64_t>(out, centralOffset);
  put<uint32_t>(out, kLocatorSignature);
  put<uint32_t>(out, 0);
  put<uint64_t>(out, end64Offset);
  put<uint32_t>(out, 1);  // disks
  put<uint32_t>(out, kEndSignature);
  put<uint16_t>(out, 0);
  put<uint16_t>(out, 0);
  put<uint16_t>(out, 0xFFFF);  // counts, size and offset in the ZIP64 record
  put<uint16_t>(out, 0xFFFF);
  put<uint32_t>(out, 0xFFFFFFFFu);
  put<uint32_t>(out, 0xFFFFFFFFu);
  put<uint16_t>(out, 0);  // comment
}

std::string zip(const std::vector<Member>& members) {
  std::string out, central;
  for (const Member& m : members) {
    const uint64_t offset = out.size();
    const uint32_t crc = crc32(m.data);
    putLocal(out, m, crc);
    putCentral(central, m, crc, offset);
  }
  const uint64_t centralOffset = out.size();
  out += central;
  putEnd(out, members.size(), central.size(), centralOffset);
  return out;
}

// Reading: every offset and size checked against the bytes there are.
class Reader {
 public:
  Reader(const std::string& bytes, std::string name) : b_(bytes), name_(std::move(name)) {}

  [[noreturn]] void fail(const std::string& what) const { throw InvalidArgument(name_, what); }
  const std::string& name() const { return name_; }

  template <typename T>
  T get(uint64_t at) const {
    if (at > b_.size() || sizeof(T) > b_.size() - at) fail("truncated (a record runs past the end)");
    uint64_t v = 0;
    for (size_t i = 0; i < sizeof(T); ++i) v |= uint64_t(static_cast<unsigned char>(b_[at + i])) << (8 * i);
    return static_cast<T>(v);
  }
  std::string slice(uint64_t at, uint64_t size) const {
    if (at > b_.size() || size > b_.size() - at) fail("truncated (a member runs past the end)");
    return b_.substr(at, size);
  }

  // The members of a stored (uncompressed) ZIP archive, ZIP64 or not (numpy's np.savez
  // writes ZIP64 records only for large files; Lava always does).
  std::map<std::string, std::string> members() const {
    if (b_.size() < 22) fail("not a checkpoint (too short for a ZIP archive)");
    const uint64_t end = b_.size() - 22;  // no archive comment: Lava and numpy write none
    if (get<uint32_t>(end) != kEndSignature) {
      if (b_.compare(0, 4, "PK\x03\x04") == 0) fail("truncated (no end of the ZIP archive)");
      fail("not a checkpoint (not a ZIP archive)");
    }
    uint64_t count = get<uint16_t>(end + 10), at = get<uint32_t>(end + 16);
    if (end >= 20 && get<uint32_t>(end - 20) == kLocatorSignature) {
      const uint64_t end64 = get<uint64_t>(end - 20 + 8);
      if (get<uint32_t>(end64) != kEnd64Signature) fail("not a checkpoint (a broken ZIP64 record)");
      count = get<uint64_t>(end64 + 32);
      at = get<uint64_t>(end64 + 48);
    }
    if (count > 64) fail("not a checkpoint (" + std::to_string(count) + " members)");
    std::map<std::string, std::string> out;
    for (uint64_t i = 0; i < count; ++i) {
      if (get<uint32_t>(at) != kCentralSignature) fail("not a checkpoint (a broken directory)");
      if (get<uint16_t>(at + 10) != 0)
        fail("not a checkpoint (a compressed member; Lava reads stored ones, as np.savez writes)");
      const uint32_t crc = get<uint32_t>(at + 16);
      uint64_t compressed = get<uint32_t>(at + 20), size = get<uint32_t>(at + 24),
               local = get<uint32_t>(at + 42);
      const uint16_t nameLength = get<uint16_t>(at + 28), extraLength = get<uint16_t>(at + 30),
                     commentLength = get<uint16_t>(at + 32);
      const std::string name = slice(at + 46, nameLength);
      // ZIP64: the fields that read 0xFFFFFFFF follow in the extra field, in this order.
      for (uint64_t e = at + 46 + nameLength; e + 4 <= at + 46 + nameLength + extraLength;) {
        const uint16_t id = get<uint16_t>(e), length = get<uint16_t>(e + 2);
        if (id == kZip64Extra) {
          uint64_t field = e + 4;
          if (size == 0xFFFFFFFFu) size = get<uint64_t>(field), field += 8;
          if (compressed == 0xFFFFFFFFu) compressed = get<uint64_t>(field), field += 8;
          if (local == 0xFFFFFFFFu) local = get<uint64_t>(field);
        }
        e += 4 + uint64_t(length);
      }
      if (compressed != size) fail("not a checkpoint (member " + name + " is not stored)");
      if (get<uint32_t>(local) != kLocalSignature) fail("not a checkpoint (a broken member)");
      const uint64_t data =
          local + 30 + get<uint16_t>(local + 26) + uint64_t(get<uint16_t>(local + 28));
      std::string bytes = slice(data, size);
      if (compareSums && crc32(bytes) != crc)
        fail("CRC mismatch in " + name + " (the file is corrupt)");
      out[name] = std::move(bytes);
      at += 46 + uint64_t(nameLength) + extraLength + commentLength;
    }
    return out;
  }

 private:
  const std::string& b_;
  std::string name_;
};

// A member's .npy header (the dictionary's text) and where its data starts; versions 1.0 to
// 3.0, as numpy writes them (it pads headers its own way).
struct Npy {
  std::string header;
  size_t data = 0;
};

Npy npyOf(const Reader& r, const std::map<std::string, std::string>& members,
          const std::string& member) {
  const auto it = members.find(member + ".npy");
  if (it == members.end()) r.fail("not a checkpoint (no " + member + " array)");
  const std::string& b = it->second;
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0)
    r.fail(member + " is not a .npy array");
  const int major = static_cast<unsigned char>(b[6]);
  const Reader field(b, r.name());
  const uint64_t length = major == 1 ? field.get<uint16_t>(8) : field.get<uint32_t>(8);
  const size_t start = major == 1 ? 10 : 12;
  if (major < 1 || major > 3 || length > b.size() - start)
    r.fail(member + " has a broken .npy header");
  return {b.substr(start, length), size_t(start + length)};
}

// The data of `member`, after checking its header says `descr`, C order and `shape`.
std::string npyData(const Reader& r, const std::map<std::string, std::string>& members,
                    const std::string& member, const std::string& descr, const std::string& shape) {
  const Npy npy = npyOf(r, members, member);
  if (npy.header.find("'descr': " + descr) == std::string::npos ||
      npy.header.find("'fortran_order': False") == std::string::npos ||
      npy.header.find("'shape': " + shape) == std::string::npos)
    r.fail(member + " is not " + descr + " of shape " + shape);
  return members.at(member + ".npy").substr(npy.data);
}

// The first dimension a member's header gives ("'shape': (N," or "(N)").
uint64_t leadingDimension(const Reader& r, const std::map<std::string, std::string>& members,
                          const std::string& member) {
  const std::string header = npyOf(r, members, member).header;
  const size_t shape = header.find("'shape': (");
  if (shape == std::string::npos) r.fail(member + " has no shape");
  uint64_t n = 0;
  size_t at = shape + 10, digits = 0;
  while (at < header.size() && std::isdigit(static_cast<unsigned char>(header[at])) && digits < 19)
    n = n * 10 + uint64_t(header[at++] - '0'), ++digits;
  if (digits == 0) r.fail(member + " has no shape");
  return n;
}

// A checkpoint's arrays, each read after checking its header's type and shape.
struct Arrays {
  std::string format, sceneText, step, clock, particles, hash, checksum;
  std::string temperature, crust, pressure;  // empty without a flow, an implicit flow
  uint64_t emitters = 0, slots = 0;
  bool flow = false, implicit = false;
};

// The format array, once it names the one format this Lava reads.
std::string formatOf(const Reader& r, const std::map<std::string, std::string>& members) {
  const std::string format = npyData(r, members, "format", "'<u4'", "(1,)");
  uint32_t version = 0;
  std::memcpy(&version, format.data(), std::min<size_t>(4, format.size()));
  if (format.size() != 4) r.fail("not a checkpoint (a broken format array)");
  if (version != kCheckpointFormat)
    r.fail("checkpoint format " + std::to_string(version) + "; this Lava reads format " +
           std::to_string(kCheckpointFormat));
  return format;
}

// Every array, in the order their failures are reported (format first, the flow's last).
Arrays arraysOf(const Reader& r, const std::map<std::string, std::string>& members) {
  Arrays a;
  a.format = formatOf(r, members);
  a.sceneText =
      npyData(r, members, "scene", "'|u1'", shapeOf(leadingDimension(r, members, "scene")));
  a.step = npyData(r, members, "step", "'<u8'", "()");
  a.emitters = leadingDimension(r, members, "clock");
  a.clock = npyData(r, members, "clock", kClockDescr, shapeOf(a.emitters));
  a.slots = leadingDimension(r, members, "particles");
  a.particles = npyData(r, members, "particles", "'<f4'", shapeOf(a.slots, 8));
  a.hash = npyData(r, members, "hash", "'<u8'", "(1,)");
  a.checksum = npyData(r, members, "checksum", "'<u8'", "(1,)");
  // A flow's arrays, when the file has them (its scene then has a flow: checked later).
  a.flow = members.count("temperature.npy") != 0 || members.count("crust.npy") != 0;
  if (a.flow) {
    a.temperature = npyData(r, members, "temperature", "'<f4'", shapeOf(a.slots));
    a.crust = npyData(r, members, "crust", "'|u1'", shapeOf(a.slots));
  }
  a.implicit = members.count("pressure.npy") != 0;  // an implicit flow's pressures
  if (a.implicit) a.pressure = npyData(r, members, "pressure", "'<f4'", shapeOf(a.slots));
  return a;
}

// Fails unless every array holds what its shape says and the checksum matches them all.
void checkArrays(const Reader& r, const Arrays& a) {
  if (a.step.size() != 8 || a.clock.size() != a.emitters * 20 ||
      a.particles.size() != a.slots * 32 || a.hash.size() != 8 || a.checksum.size() != 8 ||
      (a.flow && (a.temperature.size() != a.slots * 4 || a.crust.size() != a.slots)) ||
      (a.implicit && a.pressure.size() != a.slots * 4))
    r.fail("truncated (an array is shorter than its shape)");
  uint64_t sum = common::kFnvOffset, expected = 0;
  for (const std::string* part : std::initializer_list<const std::string*>{
           &a.format, &a.sceneText, &a.step, &a.clock, &a.particles, &a.temperature, &a.crust,
           &a.pressure})
    sum = common::fnv1a(sum, part->data(), part->size());
  std::memcpy(&expected, a.checksum.data(), 8);
  if (compareSums && sum != expected)
    r.fail("checksum mismatch (the file is corrupt or was edited)");
}

// The checkpoint's scene, parsed and checked, or a failure naming the checkpoint.
Scene sceneOf(const Reader& r, const std::string& sceneText) {
  try {
    Scene scene = parseScene(sceneText, r.name() + " (its scene)");
    checkScene(scene);  // how its keys bound each other, too
    return scene;
  } catch (const InvalidArgument& e) {
    r.fail(std::string("its scene does not load: ") + e.what());
  }
}

// Fills `state` from the arrays, whose lengths checkArrays has checked.
void readState(const Arrays& a, const std::string& name, State& state) {
  state.step = Reader(a.step, name).get<uint64_t>(0);
  state.clocks.resize(a.emitters);
  const Reader c(a.clock, name);
  for (uint64_t k = 0; k < a.emitters; ++k) {
    const uint64_t bits = c.get<uint64_t>(20 * k);
    std::memcpy(&state.clocks[k].accumulator, &bits, 8);
    state.clocks[k].serial = c.get<uint64_t>(20 * k + 8);
    state.clocks[k].head = c.get<uint32_t>(20 * k + 16);
  }
  state.particles.resize(a.slots);
  if (!a.particles.empty())
    std::memcpy(state.particles.data(), a.particles.data(), a.particles.size());
  state.temperature.resize(a.temperature.size() / 4);
  if (!a.temperature.empty())
    std::memcpy(state.temperature.data(), a.temperature.data(), a.temperature.size());
  state.crust.assign(a.crust.begin(), a.crust.end());
  state.pressure.resize(a.pressure.size() / 4);
  if (!a.pressure.empty())
    std::memcpy(state.pressure.data(), a.pressure.data(), a.pressure.size());
}

}  // namespace

void compareCheckpointSums(bool compare) {
  compareSums = compare;
}

std::string checkpointBytes(const Scene& scene, const State& state) {
  checkScene(scene);
  checkState(scene, state);
  const std::string format = bytesOf(&kCheckpointFormat, 1);
  const std::string sceneText = toToml(scene);
  std::string step;
  put<uint64_t>(step, state.step);
  const std::string clock = clockData(state);
  const std::string particles = bytesOf(state.particles.data(), state.particles.size());
  // A flow's temperatures and crust flags (empty without one) join the checksum.
  const std::string temperature = bytesOf(state.temperature.data(), state.temperature.size());
  const std::string crust = bytesOf(state.crust.data(), state.crust.size());
  const std::string pressure = bytesOf(state.pressure.data(), state.pressure.size());
  uint64_t checksum = common::kFnvOffset;
  for (const std::string* part : std::initializer_list<const std::string*>{
           &format, &sceneText, &step, &clock, &particles, &temperature, &crust, &pressure})
    checksum = common::fnv1a(checksum, part->data(), part->size());
  const uint64_t hash = stateHash(state.particles);
  const uint64_t slots = state.particles.size();
  std::vector<Member> members;
  members.push_back({"format.npy", common::npyHeader("'<u4'", "(1,)") + format});
  members.push_back({"scene.npy", common::npyHeader("'|u1'", shapeOf(sceneText.size())) + sceneText});
  members.push_back({"step.npy", common::npyHeader("'<u8'", "()") + step});
  members.push_back({"clock.npy", common::npyHeader(kClockDescr, shapeOf(state.clocks.size())) + clock});
  members.push_back({"particles.npy", common::npyHeader("'<f4'", shapeOf(slots, 8)) + particles});
  if (scene.flow) {
    members.push_back({"temperature.npy", common::npyHeader("'<f4'", shapeOf(slots)) + temperature});
    members.push_back({"crust.npy", common::npyHeader("'|u1'", shapeOf(slots)) + crust});
  }
  if (!state.pressure.empty())
    members.push_back({"pressure.npy", common::npyHeader("'<f4'", shapeOf(slots)) + pressure});
  members.push_back({"state.npy", common::npyHeader("'<f4'", shapeOf(slots, common::stateColumns(state))) + common::stateTable(state)});
  members.push_back({"hash.npy", common::npyHeader("'<u8'", "(1,)") + bytesOf(&hash, 1)});
  members.push_back({"checksum.npy", common::npyHeader("'<u8'", "(1,)") + bytesOf(&checksum, 1)});
  return zip(members);
}

void writeCheckpoint(const std::string& path, const Scene& scene, const State& state) {
  const std::string bytes = checkpointBytes(scene, state);
  try {
    common::writeFileAtomically(path, bytes);
  } catch (const ResourceError& e) {
    throw ResourceError(std::string("checkpoint: ") + e.what());
  }
}

Snapshot parseCheckpoint(const std::string& bytes, const std::string& name) {
  const Reader r(bytes, name);
  const auto members = r.members();
  const Arrays a = arraysOf(r, members);
  checkArrays(r, a);
  Snapshot s;
  s.scene = sceneOf(r, a.sceneText);
  // A scene that names no solver and a flow without pressures: written before `solver`
  // existed, when the flow was the explicit one (one naming the implicit flow without its
  // pressures is refused below, as its state does not fit).
  if (s.scene.flow && !a.implicit && a.sceneText.find("\nsolver = ") == std::string::npos)
    s.scene.flow->solver = FlowSolver::Explicit;
  readState(a, name, s.state);
  uint64_t stored = 0;
  std::memcpy(&stored, a.hash.data(), 8);
  if (stateHash(s.state.particles) != stored) r.fail("state hash mismatch (the file is corrupt)");
  try {
    checkState(s.scene, s.state);
  } catch (const InvalidArgument& e) {
    r.fail(std::string("its state does not fit its scene: ") + e.what());
  }
  return s;
}

Snapshot readCheckpoint(const std::string& path) {
  return parseCheckpoint(common::readWholeFile(path, "a checkpoint"), path);
}

}  // namespace lava
