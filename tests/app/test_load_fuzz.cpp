// The whole load path fuzzed, VTK's and OpenVDB's readers included (issue 18): a small honest
// file of every readable format, then deterministic (seeded) mutations of it (truncations at many
// offsets, byte flips, numbers of its header replaced by huge ones), each read the way `prismoid
// info` and `prismoid render` read it: app::run_cli({"info", FILE}) and app::load_dataset. Every
// result must be a load or an InputError naming the file; never a crash of this process, a
// deadlocked reader (one whose CPU time stands still for kStillSeconds is killed and counted: a
// slow honest read keeps computing), a hang (a load still running past the product's own read
// limit is cancelled and counted), or an allocation without end (this process's and its
// readers' peak memory is checked at the end).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <atomic>
#include <csignal>
#include <map>
#include <thread>

#include <sys/resource.h>
#include <unistd.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkImageData.h>
#include <vtkMetaImageWriter.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLWriter.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridWriter.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLMultiBlockDataWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "app/cli.hpp"
#include "app/common/dataset_loader.hpp"
#include "io/isolated_read.hpp"
#include "io/progress.hpp"
#include "io/vdb_io.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "support/exodus_file.hpp"
#include "support/processes.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// A reader that has used no CPU for this long is deadlocked (issue 40: a child waiting for ever
// in TBB at 0 % CPU, which the product's time limit then reported as a corrupt file).
constexpr double kStillSeconds = 10.0;
// Beyond the product's own limit (io::read_limits), the test stops waiting.
constexpr double kHangMarginSeconds = 30.0;

fs::path scratch() {
  static const fs::path dir = [] {
    fs::path d = fs::temp_directory_path() / ("prismoid_load_fuzz_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }();
  return dir;
}

// ---- seed files --------------------------------------------------------------------------------

vtkSmartPointer<vtkUnstructuredGrid> ball_grid() {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1.0);
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  vtkNew<vtkPoints> points;
  for (const auto& p : ball.points) points->InsertNextPoint(p.x, p.y, p.z);
  grid->SetPoints(points);
  for (const auto& t : ball.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  vtkNew<vtkDoubleArray> sigma;
  sigma->SetName("extinction");
  for (size_t i = 0; i < ball.tets.size(); ++i) sigma->InsertNextValue(1.0 + 0.01 * double(i));
  grid->GetCellData()->AddArray(sigma);
  return grid;
}

vtkSmartPointer<vtkPolyData> cube_poly() {
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  for (int i = 0; i < 8; ++i) points->InsertNextPoint(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  vtkNew<vtkCellArray> triangles;
  const vtkIdType faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                  {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) triangles->InsertNextCell(3, f);
  poly->SetPoints(points);
  poly->SetPolys(triangles);
  return poly;
}

vtkSmartPointer<vtkImageData> small_image() {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(5, 4, 3);
  vtkNew<vtkFloatArray> density;
  density->SetName("density");
  for (int i = 0; i < 5 * 4 * 3; ++i) density->InsertNextValue(float(i % 7) * 0.1f);
  image->GetPointData()->SetScalars(density);
  return image;
}

std::string text_of(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// One honest file of every format Prismoid reads, each beside the files it names.
std::vector<fs::path> write_seeds() {
  const fs::path dir = scratch() / "seeds";
  fs::create_directories(dir);
  std::vector<fs::path> seeds;
  auto add = [&](const std::string& name) { return seeds.emplace_back(dir / name).string(); };
  for (const int mode : {vtkXMLWriter::Ascii, vtkXMLWriter::Binary, vtkXMLWriter::Appended}) {
    vtkNew<vtkXMLUnstructuredGridWriter> w;
    w->SetInputData(ball_grid());
    w->SetDataMode(mode);
    if (mode == vtkXMLWriter::Appended) {
      w->EncodeAppendedDataOff();
      w->SetCompressorTypeToNone();
    }
    w->SetFileName(add("ball-" + std::to_string(mode) + ".vtu").c_str());
    EXPECT_EQ(w->Write(), 1);
  }
  for (const bool binary : {false, true}) {
    vtkNew<vtkUnstructuredGridWriter> w;
    w->SetInputData(ball_grid());
    if (binary) w->SetFileTypeToBinary();
    w->SetFileName(add(binary ? "ball-binary.vtk" : "ball-ascii.vtk").c_str());
    EXPECT_EQ(w->Write(), 1);
  }
  {
    vtkNew<vtkMultiBlockDataSet> blocks;
    blocks->SetBlock(0, ball_grid());
    vtkNew<vtkXMLMultiBlockDataWriter> w;
    w->SetInputData(blocks);
    w->SetFileName(add("blocks.vtm").c_str());
    EXPECT_EQ(w->Write(), 1);
  }
  {
    vtkNew<vtkXMLUnstructuredGridWriter> w;
    w->SetInputData(ball_grid());
    w->SetFileName((dir / "piece0.vtu").c_str());
    EXPECT_EQ(w->Write(), 1);
    write_text(add("pieces.pvtu"),
               "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "  <PUnstructuredGrid GhostLevel=\"0\">\n    <PCellData><PDataArray type=\"Float64\" Name=\"extinction\"/></PCellData>\n"
               "    <PPoints><PDataArray type=\"Float32\" NumberOfComponents=\"3\"/></PPoints>\n"
               "    <Piece Source=\"piece0.vtu\"/>\n  </PUnstructuredGrid>\n</VTKFile>\n");
  }
  {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetInputData(cube_poly());
    w->SetFileName(add("cube.vtp").c_str());
    EXPECT_EQ(w->Write(), 1);
  }
  for (const bool binary : {false, true}) {
    vtkNew<vtkSTLWriter> w;
    w->SetInputData(cube_poly());
    if (binary) w->SetFileTypeToBinary();
    w->SetFileName(add(binary ? "cube-binary.stl" : "cube-ascii.stl").c_str());
    EXPECT_EQ(w->Write(), 1);
    vtkNew<vtkPLYWriter> p;
    p->SetInputData(cube_poly());
    if (binary) p->SetFileTypeToBinary();
    else p->SetFileTypeToASCII();
    p->SetFileName(add(binary ? "cube-binary.ply" : "cube-ascii.ply").c_str());
    EXPECT_EQ(p->Write(), 1);
  }
  {
    std::ostringstream obj, off;
    off << "OFF\n8 12 0\n";
    const vtkSmartPointer<vtkPolyData> cube = cube_poly();
    for (vtkIdType i = 0; i < 8; ++i) {
      double p[3];
      cube->GetPoint(i, p);
      obj << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
      off << p[0] << " " << p[1] << " " << p[2] << "\n";
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < 12; ++c) {
      cube->GetCellPoints(c, ids);
      obj << "f " << ids->GetId(0) + 1 << " " << ids->GetId(1) + 1 << " " << ids->GetId(2) + 1 << "\n";
      off << "3 " << ids->GetId(0) << " " << ids->GetId(1) << " " << ids->GetId(2) << "\n";
    }
    write_text(add("cube.obj"), obj.str());
    write_text(add("cube.off"), off.str());
  }
  {
    vtkNew<vtkXMLImageDataWriter> w;
    w->SetInputData(small_image());
    w->SetFileName(add("image.vti").c_str());
    EXPECT_EQ(w->Write(), 1);
  }
  for (const bool compressed : {false, true}) {
    vtkNew<vtkMetaImageWriter> w;
    w->SetInputData(small_image());
    w->SetCompression(compressed);
    const std::string name = compressed ? "image.mha" : "image.mhd";
    w->SetFileName(add(name).c_str());
    if (!compressed) w->SetRAWFileName((dir / "image.raw").c_str());
    w->Write();
    EXPECT_TRUE(fs::exists(dir / name));
  }
  {
    std::string inr = "#INRIMAGE-4#{\nXDIM=5\nYDIM=4\nZDIM=3\nVDIM=1\nTYPE=unsigned fixed\nPIXSIZE=8 bits\nCPU=decm\nVX=1\nVY=1\nVZ=1\n";
    inr.resize(252, '\n');
    inr += "##}\n";
    for (int i = 0; i < 5 * 4 * 3; ++i) inr.push_back(char(i % 7));
    write_text(add("image.inr"), inr);
  }
  {
    SurfaceMesh cube;
    cube.name = "cube";
    const vtkSmartPointer<vtkPolyData> poly = cube_poly();
    for (vtkIdType i = 0; i < 8; ++i) {
      double p[3];
      poly->GetPoint(i, p);
      cube.points.emplace_back(p[0], p[1], p[2]);
    }
    vtkNew<vtkIdList> ids;
    for (vtkIdType c = 0; c < 12; ++c) {
      poly->GetCellPoints(c, ids);
      cube.triangles.push_back({uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)), uint32_t(ids->GetId(2))});
    }
    io::VdbWriteOptions vdb;
    vdb.voxel_size = 0.25;
    io::write_vdb_from_surface(add("cube.vdb"), cube, vdb);
  }
  // A time series: ParaView's collection of two steps, the meshes written above beside it.
  std::ofstream(add("series.pvd")) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n"
                                      "    <DataSet timestep=\"0\" part=\"0\" file=\"ball-0.vtu\"/>\n"
                                      "    <DataSet timestep=\"1.25\" part=\"0\" file=\"ball-1.vtu\"/>\n  </Collection>\n</VTKFile>\n";
  {
    // Exodus II (netCDF classic): the unit ball's tetrahedra in one block, an element variable over
    // two steps, with the library VTK's reader uses.
    const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1.0);
    test::ExodusFileSpec spec = test::exodus_of(ball);
    spec.element_variables = {"density"};
    spec.times = {0.0, 0.5};
    spec.blocks[0].values = {{ball.cell_extinction}, {ball.cell_extinction}};
    test::write_exodus(add("ball.exo"), spec);
  }
  return seeds;
}

// ---- mutations -----------------------------------------------------------------------------------

struct Mutant {
  std::string how;
  std::string bytes;
};

std::vector<Mutant> mutants_of(const std::string& seed, uint32_t salt) {
  std::vector<Mutant> out;
  std::mt19937 random(1800 + salt);
  // Truncations: at sixteenths of the file (the empty file first), and just short of its end.
  for (size_t k = 0; k < 16; ++k) out.push_back({"cut at " + std::to_string(seed.size() * k / 16), seed.substr(0, seed.size() * k / 16)});
  for (size_t short_by : {size_t(1), size_t(7)})
    if (seed.size() > short_by) out.push_back({"cut " + std::to_string(short_by) + " short", seed.substr(0, seed.size() - short_by)});
  // Byte flips: 1 to 8 random bytes anywhere.
  for (int variant = 0; variant < 12; ++variant) {
    Mutant m{"flips", seed};
    for (int f = 0; f <= variant % 8; ++f) {
      const size_t at = random() % seed.size();
      m.bytes[at] = char(random() & 0xff);
      m.how += " " + std::to_string(at);
    }
    out.push_back(m);
  }
  // Sizes: numbers written in the first 4 KiB (header counts, extents, offsets) made huge or
  // negative, one at a time, and binary words near the start made huge.
  std::vector<std::pair<size_t, size_t>> numbers;  // (start, length)
  for (size_t i = 0; i < std::min<size_t>(seed.size(), 4096); ++i)
    if (std::isdigit(static_cast<unsigned char>(seed[i])) && (i == 0 || !std::isdigit(static_cast<unsigned char>(seed[i - 1])))) {
      size_t n = 0;
      while (i + n < seed.size() && std::isdigit(static_cast<unsigned char>(seed[i + n]))) ++n;
      numbers.emplace_back(i, n);
    }
  const char* const huge[] = {"2000000000", "9223372036854775807", "4294967296", "-1"};
  for (int variant = 0; variant < 10 && !numbers.empty(); ++variant) {
    const auto [at, length] = numbers[random() % numbers.size()];
    Mutant m{"number at " + std::to_string(at) + " -> " + huge[variant % 4], seed};
    m.bytes.replace(at, length, huge[variant % 4]);
    out.push_back(m);
  }
  for (int variant = 0; variant < 4 && seed.size() > 8; ++variant) {
    const size_t at = random() % std::min<size_t>(seed.size() - 4, 512);
    Mutant m{"word at " + std::to_string(at), seed};
    const uint32_t word = variant % 2 ? 0x7fffffffu : 0xffffffffu;
    std::memcpy(m.bytes.data() + at, &word, 4);
    out.push_back(m);
  }
  return out;
}

// ---- the deadlock watch ----------------------------------------------------------------------------

// Watches the readers while the test runs (this process's grandchildren: its children are the
// idle reader hosts): one whose CPU time stands still for kStillSeconds is deadlocked; it is
// killed (the load then fails, and the test says why) and counted.
class DeadlockWatch {
 public:
  DeadlockWatch() : thread_([this] { watch(); }) {}
  ~DeadlockWatch() {
    stop_ = true;
    thread_.join();
  }
  // The deadlocks seen since the last call.
  size_t take() { return found_.exchange(0); }

 private:
  void watch() {
    struct Seen {
      uint64_t ticks;
      Clock::time_point since;
    };
    std::map<pid_t, Seen> seen;
    while (!stop_) {
      const auto now = Clock::now();
      std::map<pid_t, Seen> next;
      const std::map<pid_t, test::ProcessStat> table = test::process_table();
      for (const pid_t pid : test::running_readers(table)) {
        const uint64_t ticks = table.at(pid).cpu_ticks;
        const auto it = seen.find(pid);
        Seen s = it != seen.end() && it->second.ticks == ticks ? it->second : Seen{ticks, now};
        if (std::chrono::duration<double>(now - s.since).count() > kStillSeconds) {
          ++found_;
          ::kill(pid, SIGKILL);
          continue;
        }
        next[pid] = s;
      }
      seen = std::move(next);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
  std::atomic<bool> stop_{false};
  std::atomic<size_t> found_{0};
  std::thread thread_;
};

// ---- the load path -------------------------------------------------------------------------------

struct Outcome {
  bool loaded = false;
  std::string error;  // the InputError's text, or what went wrong (a failure)
  bool failure = false;
};

// render's path: the dataset as `render FILE` loads it, with a watchdog that cancels a hang.
Outcome load_as_render(const std::string& path) {
  Outcome o;
  const auto start = Clock::now();
  const double limit = io::read_limits(path).seconds + kHangMarginSeconds;
  bool hung = false;
  try {
    app::LoadRequest request;
    request.path = path;
    const TetMesh mesh = app::load_dataset(request, [&](double, const std::string&) {
      hung = Clock::now() - start > std::chrono::duration<double>(limit);
      return !hung;
    });
    validate(mesh);
    o.loaded = true;
  } catch (const InputError& e) {
    o.error = e.what();
  } catch (const io::Cancelled&) {
    o.failure = true;
    o.error = hung ? "hung: still loading after " + std::to_string(limit) + " s" : "cancelled";
  } catch (const std::exception& e) {
    o.failure = true;
    o.error = std::string("not an InputError: ") + e.what();
  }
  return o;
}

// info's path: the verb itself, in this process, its streams captured.
Outcome describe_as_info(const std::string& path) {
  std::ostringstream out, err;
  std::streambuf* cout_buf = std::cout.rdbuf(out.rdbuf());
  std::streambuf* cerr_buf = std::cerr.rdbuf(err.rdbuf());
  const int code = app::run_cli({"info", path});
  std::cout.rdbuf(cout_buf);
  std::cerr.rdbuf(cerr_buf);
  Outcome o;
  o.loaded = code == 0;
  o.error = err.str();
  o.failure = code != 0 && code != 2;
  if (code != 0 && code != 2) o.error = "exit code " + std::to_string(code) + ": " + o.error;
  return o;
}

uint64_t peak_kib(int who) {
  rusage usage{};
  ::getrusage(who, &usage);
  return uint64_t(usage.ru_maxrss);
}

TEST(LoadFuzz, EveryMutationOfEveryFormatLoadsOrIsAnInputErrorNamingTheFile) {
  ::setenv("XDG_CACHE_HOME", (scratch() / "cache").c_str(), 1);  // TetGen's results stay here
  const std::vector<fs::path> seeds = write_seeds();
  ASSERT_EQ(seeds.size(), 21u);  // 16 extensions, several in ASCII and binary
  DeadlockWatch deadlocks;
  const auto start = Clock::now();
  size_t runs = 0, loads = 0, refusals = 0;
  uint64_t largest_limit = 0;  // of the readers' memory limits
  for (size_t s = 0; s < seeds.size(); ++s) {
    const fs::path& seed = seeds[s];
    // PRISMOID_LOAD_FUZZ_ONLY=NAME: only the seeds whose file name holds NAME (to reproduce a finding).
    if (const char* only = std::getenv("PRISMOID_LOAD_FUZZ_ONLY"); only && seed.filename().string().find(only) == std::string::npos) continue;
    SCOPED_TRACE(seed.filename().string());
    // The honest seed loads both ways.
    const Outcome honest = load_as_render(seed.string());
    EXPECT_TRUE(honest.loaded) << honest.error;
    const Outcome described = describe_as_info(seed.string());
    EXPECT_TRUE(described.loaded) << described.error;
    EXPECT_EQ(deadlocks.take(), 0u);
    const std::string bytes = text_of(seed);
    largest_limit = std::max(largest_limit, io::read_limits(seed.string()).memory_bytes);
    // Mutants sit beside the seed (a .vtm's blocks and a .mhd's raw data are found there).
    const fs::path mutant = seed.parent_path() / ("mutant-" + seed.filename().string());
    const auto seed_start = Clock::now();
    for (const Mutant& m : mutants_of(bytes, uint32_t(s))) {
      write_text(mutant, m.bytes);
      for (const bool info : {false, true}) {
        const auto load_start = Clock::now();
        Outcome o = info ? describe_as_info(mutant.string()) : load_as_render(mutant.string());
        if (deadlocks.take() > 0) {
          o.failure = true;
          o.error = "deadlocked: the reader used no CPU for " + std::to_string(kStillSeconds) + " s (" + o.error + ")";
        }
        if (const double took = std::chrono::duration<double>(Clock::now() - load_start).count(); took > (std::getenv("PRISMOID_LOAD_FUZZ_SLOW") ? std::atof(std::getenv("PRISMOID_LOAD_FUZZ_SLOW")) : 1.0))
          std::cout << "slow: " << (info ? "info " : "render ") << seed.filename().string() << " " << m.how << ": " << took << " s\n";
        ++runs;
        (o.loaded ? loads : refusals)++;
        if (o.failure) {  // kept for reproducing: prismoid info|render FILE
          const fs::path kept = fs::temp_directory_path() / "prismoid_load_fuzz_findings" / (std::to_string(s) + "-" + std::to_string(runs) + "-" + seed.filename().string());
          fs::create_directories(kept.parent_path());
          fs::copy_file(mutant, kept, fs::copy_options::overwrite_existing);
          ADD_FAILURE() << (info ? "info " : "render ") << m.how << ": " << o.error << " (the file: " << kept.string() << ")";
        }
        if (!o.loaded && !o.failure) {
          EXPECT_NE(o.error.find(mutant.string()), std::string::npos) << (info ? "info " : "render ") << m.how << ": " << o.error;
        }
      }
    }
    std::cout << seed.filename().string() << ": " << std::chrono::duration<double>(Clock::now() - seed_start).count() << " s\n";
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::cout << runs << " mutant loads (" << loads << " loaded, " << refusals << " refused) in " << seconds << " s; peak memory "
            << peak_kib(RUSAGE_SELF) / 1024 << " MiB here, " << io::largest_reader_memory_bytes() / 1048576 << " MiB in a reader\n";
  // Nothing grew here; a reader stayed within its file's memory limit (it also holds the pages of
  // the program and its libraries, which this process holds too).
  EXPECT_LT(peak_kib(RUSAGE_SELF), uint64_t(1) << 20) << "KiB";
  EXPECT_GT(io::largest_reader_memory_bytes(), uint64_t(0));
  EXPECT_LE(io::largest_reader_memory_bytes() / 1024, peak_kib(RUSAGE_SELF) + largest_limit / 1024) << "KiB";
  fs::remove_all(scratch());
}

}  // namespace
}  // namespace prismoid
