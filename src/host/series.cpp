#include "series.h"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "common/files.h"
#include "common/hash.h"
#include "lava/error.h"
#include "output.h"

namespace lava::host {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the .vtp files say LittleEndian");

// The appended block of one array and the XML element that points into it.
class Appended {
 public:
  template <typename T>
  void array(std::string& xml, const char* indent, const char* type, const char* name,
             unsigned components, const std::vector<T>& values) {
    char element[256];
    std::snprintf(element, sizeof(element),
                  "%s<DataArray type=\"%s\" Name=\"%s\" NumberOfComponents=\"%u\" "
                  "NumberOfTuples=\"%zu\" format=\"appended\" offset=\"%zu\"/>\n",
                  indent, type, name, components, values.size() / components, data_.size());
    xml += element;
    const uint64_t bytes = values.size() * sizeof(T);
    data_.append(reinterpret_cast<const char*>(&bytes), sizeof(bytes));
    data_.append(reinterpret_cast<const char*>(values.data()), bytes);
  }
  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

std::string timeText(const Scene& scene, uint64_t step) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.17g", double(step) * scene.dt);
  return text;
}

// The step of "step_<digits>.vtp", or false.
bool sampleStep(const std::string& name, uint64_t& step) {
  if (name.size() <= 9 || name.size() > 9 + 19 || name.compare(0, 5, "step_") != 0 ||
      name.compare(name.size() - 4, 4, ".vtp") != 0)
    return false;
  const size_t digits = name.size() - 9;  // after "step_", before ".vtp"
  step = 0;
  for (size_t i = 5; i < 5 + digits; ++i) {
    if (name[i] < '0' || name[i] > '9') return false;
    step = step * 10 + uint64_t(name[i] - '0');
  }
  return true;
}

// The value of `key="..."` in `line`, or "".
std::string attribute(const std::string& line, const std::string& key) {
  const size_t at = line.find(" " + key + "=\"");
  if (at == std::string::npos) return "";
  const size_t begin = at + key.size() + 3, end = line.find('"', begin);
  return end == std::string::npos ? "" : line.substr(begin, end - begin);
}

// The alive particles' point data, slot by slot: what a sample's .vtp lists.
struct Columns {
  std::vector<float> points, velocity, speed, age, temperature;
  std::vector<int32_t> emitter;
  std::vector<int64_t> slot, offsets;
  std::vector<uint8_t> crust;
};

// The columns of the alive particles (age >= 0), each emitter's ring in turn; with `flow`,
// their temperatures and crust flags too.
Columns aliveColumns(const Scene& scene, const State& state, bool flow) {
  Columns c;
  uint64_t first = 0;  // the slot where the current emitter's ring begins
  for (size_t e = 0; e < scene.emitters.size(); ++e) {
    const uint64_t end = first + scene.emitters[e].particles;
    for (uint64_t i = first; i < end; ++i) {
      const Particle& p = state.particles[i];
      if (!(p.age >= 0.0f)) continue;
      c.points.insert(c.points.end(), {p.px, p.py, p.pz});
      c.velocity.insert(c.velocity.end(), {p.vx, p.vy, p.vz});
      // In double, rounded once: numpy gives the same float from the .npy columns.
      const double vx = p.vx, vy = p.vy, vz = p.vz;
      c.speed.push_back(float(std::sqrt(vx * vx + vy * vy + vz * vz)));
      c.age.push_back(p.age);
      c.emitter.push_back(int32_t(e));
      c.slot.push_back(int64_t(i));
      c.offsets.push_back(int64_t(c.slot.size()));
      if (flow) {
        c.temperature.push_back(state.temperature[i]);
        c.crust.push_back(state.crust[i]);
      }
    }
    first = end;
  }
  return c;
}

}  // namespace

uint64_t sceneHash(const Scene& scene) {
  const std::string text = toToml(scene);
  return common::fnv1a(common::kFnvOffset, text.data(), text.size());
}

std::string sampleName(uint64_t step) {
  char name[40];
  std::snprintf(name, sizeof(name), "step_%012llu.vtp", static_cast<unsigned long long>(step));
  return name;
}

std::string vtpBytes(const Scene& scene, const State& state) {
  checkState(scene, state);
  const bool flow = !state.temperature.empty();
  const Columns c = aliveColumns(scene, state, flow);
  const size_t n = c.age.size();
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n  <PolyData>\n    <FieldData>\n";
  Appended blocks;
  blocks.array(xml, "      ", "UInt64", "step", 1, std::vector<uint64_t>{state.step});
  blocks.array(xml, "      ", "Float64", "TimeValue", 1,
               std::vector<double>{double(state.step) * scene.dt});
  blocks.array(xml, "      ", "UInt64", "scene_hash", 1, std::vector<uint64_t>{sceneHash(scene)});
  blocks.array(xml, "      ", "UInt64", "state_hash", 1, std::vector<uint64_t>{stateHash(state)});
  char piece[200];
  std::snprintf(piece, sizeof(piece),
                "    </FieldData>\n    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"%zu\" "
                "NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n",
                n, n);
  xml += piece;
  xml += "      <PointData Scalars=\"speed\" Vectors=\"velocity\">\n";
  const char* in = "        ";
  blocks.array(xml, in, "Float32", "velocity", 3, c.velocity);
  blocks.array(xml, in, "Float32", "speed", 1, c.speed);
  blocks.array(xml, in, "Float32", "age", 1, c.age);
  blocks.array(xml, in, "Int32", "emitter", 1, c.emitter);
  blocks.array(xml, in, "Int64", "slot", 1, c.slot);
  if (flow) {
    blocks.array(xml, in, "Float32", "temperature", 1, c.temperature);
    blocks.array(xml, in, "UInt8", "crust", 1, c.crust);
  }
  xml += "      </PointData>\n      <Points>\n";
  blocks.array(xml, in, "Float32", "Points", 3, c.points);
  xml += "      </Points>\n      <Verts>\n";
  std::vector<int64_t> connectivity(n);  // one vertex a point: 0, 1, 2, ...
  for (size_t i = 0; i < n; ++i) connectivity[i] = int64_t(i);
  blocks.array(xml, in, "Int64", "connectivity", 1, connectivity);
  blocks.array(xml, in, "Int64", "offsets", 1, c.offsets);
  xml += "      </Verts>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
  xml += blocks.data();
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  return xml;
}

SeriesWriter::SeriesWriter(std::string folder, uint64_t every, uint64_t firstStep, bool resumed)
    : folder_(std::move(folder)), every_(every), step_(firstStep) {
  while (folder_.size() > 1 && folder_.back() == '/') folder_.pop_back();
  const size_t slash = folder_.find_last_of('/');
  name_ = slash == std::string::npos ? folder_ : folder_.substr(slash + 1);
  if (name_.empty() || name_ == "." || name_ == ".." || every_ == 0)
    throw InvalidArgument("series", "expected a folder with a name (" + name_ +
                                        ".pvd is written beside it) and a step count of at "
                                        "least 1 between samples, got '" + folder_ + "'");
  pvd_ = folder_ + ".pvd";
  if (mkdir(folder_.c_str(), 0755) != 0 && errno != EEXIST)
    throw ResourceError("cannot create folder '" + folder_ + "': " + std::strerror(errno));
  if (resumed && access(pvd_.c_str(), F_OK) == 0) {
    // The earlier run's samples before this one's first state: the collection's own lines.
    const std::string text = common::readWholeFile(pvd_, "a series collection");
    size_t begin = 0;
    while (begin < text.size()) {
      const size_t end = std::min(text.find('\n', begin), text.size());
      const std::string line = text.substr(begin, end - begin);
      begin = end + 1;
      const std::string file = attribute(line, "file"), time = attribute(line, "timestep");
      uint64_t step = 0;
      if (file.compare(0, name_.size() + 1, name_ + "/") == 0 && !time.empty() &&
          sampleStep(file.substr(name_.size() + 1), step) && step < firstStep &&
          access((folder_ + "/" + sampleName(step)).c_str(), R_OK) == 0)
        entries_.push_back({step, time});
    }
  }
  // The folder holds exactly the samples the collection names.
  if (DIR* dir = opendir(folder_.c_str())) {
    std::vector<std::string> stale;
    while (const dirent* entry = readdir(dir)) {
      uint64_t step = 0;
      const std::string name = entry->d_name;
      if (!sampleStep(name, step) || name != sampleName(step)) continue;
      bool kept = false;
      for (const Entry& e : entries_) kept = kept || e.step == step;
      if (!kept) stale.push_back(folder_ + "/" + name);
    }
    closedir(dir);
    for (const std::string& path : stale) unlink(path.c_str());
  }
  writeCollection();
}

void SeriesWriter::write(const Scene& scene, const State& state) {
  writeFileAtomically(folder_ + "/" + sampleName(state.step), vtpBytes(scene, state));
  step_ = state.step;
  while (!entries_.empty() && entries_.back().step >= state.step) entries_.pop_back();
  entries_.push_back({state.step, timeText(scene, state.step)});
  writeCollection();
}

void SeriesWriter::sampleIfDue(Simulation& simulation) {
  if (due(step_)) write(simulation.scene(), simulation.state());
}

void SeriesWriter::advance(Simulation& simulation, uint64_t steps, Run run) {
  for (const uint64_t end = step_ + steps; step_ < end;) {
    const uint64_t batch = std::min(end - step_, every_ - step_ % every_);
    run ? run(simulation, batch) : simulation.advance(batch);
    step_ += batch;
    sampleIfDue(simulation);
  }
}

void SeriesWriter::writeCollection() const {
  std::string xml =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n  <Collection>\n";
  for (const Entry& e : entries_)
    xml += "    <DataSet timestep=\"" + e.time + "\" part=\"0\" file=\"" + name_ + "/" +
           sampleName(e.step) + "\"/>\n";
  xml += "  </Collection>\n</VTKFile>\n";
  writeFileAtomically(pvd_, xml);
}

}  // namespace lava::host
