#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <unistd.h>

#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkMetaImageWriter.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>
#include <zlib.h>

#include "io/image_volume_io.hpp"
#include "support/mesh_faces.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("prismoid_image_" + std::to_string(::getpid()) + "_" + name)).string();
}

// The voxel grid every test writes: distinct integers (the .inr stores int16), some negative, so
// misplaced voxels show.
struct Grid {
  int dims[3] = {4, 3, 5};
  glm::dvec3 origin{10.0, -3.0, 7.0};
  glm::dvec3 spacing{0.5, 2.0, 1.25};
  std::function<double(int, int, int)> value = [](int i, int j, int k) { return i + 10.0 * j + 100.0 * k - 17.0; };
};

vtkSmartPointer<vtkImageData> make_image(const Grid& g) {
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(g.dims);
  image->SetOrigin(g.origin.x, g.origin.y, g.origin.z);
  image->SetSpacing(g.spacing.x, g.spacing.y, g.spacing.z);
  vtkNew<vtkDoubleArray> density, other;
  density->SetName("density");
  other->SetName("other");
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        density->InsertNextValue(g.value(i, j, k));
        other->InsertNextValue(0.0);
      }
  image->GetPointData()->SetScalars(density);
  image->GetPointData()->AddArray(other);
  return image;
}

std::string write_vti(const Grid& g, const std::string& name) {
  const std::string path = temp_path(name);
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(make_image(g));
  EXPECT_EQ(writer->Write(), 1);
  return path;
}

std::string write_mhd(const Grid& g, const std::string& name) {
  const std::string path = temp_path(name);
  vtkNew<vtkMetaImageWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetCompression(false);
  writer->SetInputData(make_image(g));
  writer->Write();
  EXPECT_TRUE(std::filesystem::exists(path));
  return path;
}

// An INRIMAGE-4 header as CGAL writes it: KEY=value lines padded with newlines to 256 bytes.
std::string inr_header(const std::string& fields) {
  std::string header = "#INRIMAGE-4#{\n" + fields;
  header.resize(256 - 4, '\n');
  return header + "##}\n";
}

// Signed 16-bit big-endian voxels (CPU=sun), so the byte swap is exercised on this little-endian host.
std::string inr_bytes(const Grid& g, const std::string& extra_fields = "") {
  std::string fields = "XDIM=" + std::to_string(g.dims[0]) + "\nYDIM=" + std::to_string(g.dims[1]) + "\nZDIM=" +
                       std::to_string(g.dims[2]) + "\nVDIM=1\nTYPE=signed fixed\nPIXSIZE=16 bits\nSCALE=2**0\nCPU=sun\n";
  fields += "VX=" + std::to_string(g.spacing.x) + "\nVY=" + std::to_string(g.spacing.y) + "\nVZ=" + std::to_string(g.spacing.z) + "\n";
  fields += "TX=" + std::to_string(g.origin.x) + "\nTY=" + std::to_string(g.origin.y) + "\nTZ=" + std::to_string(g.origin.z) + "\n";
  fields += "#GEOMETRY=CARTESIAN\n" + extra_fields;
  std::string bytes = inr_header(fields);
  for (int k = 0; k < g.dims[2]; ++k)
    for (int j = 0; j < g.dims[1]; ++j)
      for (int i = 0; i < g.dims[0]; ++i) {
        const auto v = static_cast<uint16_t>(static_cast<int16_t>(g.value(i, j, k)));
        bytes += static_cast<char>(v >> 8);
        bytes += static_cast<char>(v & 0xff);
      }
  return bytes;
}

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

void expect_error(const std::string& path, const io::ImageReadOptions& options, const std::string& fragment) {
  try {
    io::read_image_volume(path, options);
    FAIL() << "expected an InputError containing '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// Points at origin + index * spacing carrying the voxel values, 6 positive tetrahedra per cell,
// every interior face shared by exactly two of them and every boundary face by one, and the
// volumes summing to the box's.
void expect_voxel_mesh(const TetMesh& mesh, const Grid& g) {
  const int nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
  ASSERT_EQ(mesh.points.size(), size_t(nx * ny * nz));
  ASSERT_EQ(mesh.point_scalars.size(), mesh.points.size());
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const size_t id = size_t(i + nx * (j + ny * k));
        const glm::dvec3 expected = g.origin + glm::dvec3(i, j, k) * g.spacing;
        for (int a = 0; a < 3; ++a) EXPECT_DOUBLE_EQ(mesh.points[id][a], expected[a]) << i << " " << j << " " << k;
        EXPECT_EQ(mesh.point_scalars[id], g.value(i, j, k)) << i << " " << j << " " << k;  // small integers: exact in every format
      }
  ASSERT_EQ(mesh.tets.size(), size_t(6 * (nx - 1) * (ny - 1) * (nz - 1)));
  const std::map<std::array<uint32_t, 3>, int> faces = test::face_uses(mesh);
  double volume = 0.0;
  for (const auto& t : mesh.tets) {
    const double v = signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    EXPECT_GT(v, 0.0);
    volume += v;
  }
  const glm::dvec3 lo = g.origin, hi = g.origin + glm::dvec3(nx - 1, ny - 1, nz - 1) * g.spacing;
  for (const auto& [f, count] : faces) {
    bool on_boundary = false;  // all three corners on one side of the box
    for (int a = 0; a < 3; ++a)
      for (double side : {lo[a], hi[a]})
        on_boundary |= mesh.points[f[0]][a] == side && mesh.points[f[1]][a] == side && mesh.points[f[2]][a] == side;
    EXPECT_EQ(count, on_boundary ? 1 : 2);
  }
  // Each tetrahedron's volume carries a relative rounding error of a few ulps (a 3x3 determinant of
  // exact differences), and the sum adds one ulp per term: 1e-12 is far above n * 1e-16 here.
  const glm::dvec3 size = hi - lo;
  EXPECT_NEAR(volume, size.x * size.y * size.z, 1e-12 * size.x * size.y * size.z);
}

TEST(ImageVolumeIo, ConversionReportsProgressAndCanBeCancelled) {
  const Grid g;
  const std::string path = write_vti(g, "progress.vti");
  std::vector<double> fractions;
  io::ImageReadOptions options{.role = io::ArrayRole::Scalars};
  options.progress = [&](double f, const std::string&) {
    fractions.push_back(f);
    return true;
  };
  const TetMesh mesh = io::read_image_volume(path, options);
  ASSERT_FALSE(fractions.empty());
  for (size_t i = 1; i < fractions.size(); ++i) EXPECT_GE(fractions[i], fractions[i - 1]);
  EXPECT_GE(fractions.front(), 0.0);
  EXPECT_DOUBLE_EQ(fractions.back(), 1.0);
  // Cancelling half-way stops the conversion with io::Cancelled, naming the file.
  options.progress = [](double f, const std::string&) { return f < 0.5; };
  try {
    io::read_image_volume(path, options);
    ADD_FAILURE() << "the conversion was not cancelled";
  } catch (const io::Cancelled& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(ImageVolumeIo, RecognisesImageExtensions) {
  for (const char* p : {"a.vti", "b.MHD", "c.mha", "d.inr", "e.inr.gz", "f.INR.GZ"}) EXPECT_TRUE(io::is_image_volume_path(p)) << p;
  for (const char* p : {"a.vtu", "b.vtk", "c.gz", "d.raw", "inr"}) EXPECT_FALSE(io::is_image_volume_path(p)) << p;
}

TEST(ImageVolumeIo, VtiBecomesConformingTetrahedraWithPointScalars) {
  const Grid g;
  const std::string path = write_vti(g, "grid.vti");
  const TetMesh mesh = io::read_image_volume(path, {.role = io::ArrayRole::Scalars, .density_scale = 0.5});
  expect_voxel_mesh(mesh, g);
  EXPECT_TRUE(mesh.point_extinction.empty());
  for (double s : mesh.cell_extinction) EXPECT_EQ(s, 0.5);
  // Choosing the other array by name.
  const TetMesh other = io::read_image_volume(path, {.array = "other", .role = io::ArrayRole::Scalars});
  for (double s : other.point_scalars) EXPECT_EQ(s, 0.0);
  std::filesystem::remove(path);
}

TEST(ImageVolumeIo, MhdBecomesConformingTetrahedraWithPointScalars) {
  const Grid g;
  const std::string path = write_mhd(g, "grid.mhd");
  expect_voxel_mesh(io::read_image_volume(path, {.role = io::ArrayRole::Scalars}), g);
  std::filesystem::remove(path);
  std::filesystem::remove(temp_path("grid.raw"));
  const std::string single_file = write_mhd(g, "grid.mha");  // header and voxels in one file
  expect_voxel_mesh(io::read_image_volume(single_file, {.role = io::ArrayRole::Scalars}), g);
  std::filesystem::remove(single_file);
}

TEST(ImageVolumeIo, InrBecomesConformingTetrahedraWithPointScalars) {
  const Grid g;
  const std::string path = write_file("grid.inr", inr_bytes(g));
  expect_voxel_mesh(io::read_image_volume(path, {.role = io::ArrayRole::Scalars}), g);
  std::filesystem::remove(path);
}

TEST(ImageVolumeIo, GzippedInrReadsTheSame) {
  const Grid g;
  const std::string bytes = inr_bytes(g);
  const std::string path = temp_path("grid.inr.gz");
  gzFile file = gzopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  ASSERT_EQ(gzwrite(file, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
  gzclose(file);
  expect_voxel_mesh(io::read_image_volume(path, {.role = io::ArrayRole::Scalars}), g);
  std::filesystem::remove(path);
}

TEST(ImageVolumeIo, ExtinctionRoleScalesThePointValues) {
  Grid g;
  g.value = [](int i, int j, int k) { return 1.0 + i + 2.0 * j + 3.0 * k; };
  const std::string path = write_file("ext.inr", inr_bytes(g));
  const TetMesh mesh = io::read_image_volume(path, {.density_scale = 0.25});
  ASSERT_TRUE(mesh.linear_extinction());
  for (size_t i = 0; i < mesh.points.size(); ++i) EXPECT_EQ(mesh.point_extinction[i], 0.25 * mesh.point_scalars[i]);
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    double mean = 0.0;
    for (uint32_t v : mesh.tets[c]) mean += 0.25 * mesh.point_extinction[v];
    EXPECT_DOUBLE_EQ(mesh.cell_extinction[c], mean);
  }
  // Negative voxels cannot be extinction.
  const std::string negative = write_file("neg.inr", inr_bytes(Grid{}));
  expect_error(negative, {}, "must be finite and >= 0");
  std::filesystem::remove(path);
  std::filesystem::remove(negative);
}

TEST(ImageVolumeIo, SubsampleKeepsEveryKthVoxel) {
  Grid fine;
  fine.dims[0] = 7, fine.dims[1] = 5, fine.dims[2] = 9;
  Grid coarse = fine;  // every 2nd voxel: 4 x 3 x 5 at twice the spacing
  coarse.dims[0] = 4, coarse.dims[1] = 3, coarse.dims[2] = 5;
  coarse.spacing = 2.0 * fine.spacing;
  coarse.value = [&fine](int i, int j, int k) { return fine.value(2 * i, 2 * j, 2 * k); };
  const std::string inr = write_file("fine.inr", inr_bytes(fine));
  const std::string vti = write_vti(fine, "fine.vti");
  for (const std::string& path : {inr, vti}) {
    SCOPED_TRACE(path);
    expect_voxel_mesh(io::read_image_volume(path, {.role = io::ArrayRole::Scalars, .subsample = 2}), coarse);
  }
  // Every 3rd of 7 x 5 x 9 keeps indices 0, 3, 6 / 0, 3 / 0, 3, 6.
  Grid third = fine;
  third.dims[0] = 3, third.dims[1] = 2, third.dims[2] = 3;
  third.spacing = 3.0 * fine.spacing;
  third.value = [&fine](int i, int j, int k) { return fine.value(3 * i, 3 * j, 3 * k); };
  expect_voxel_mesh(io::read_image_volume(inr, {.role = io::ArrayRole::Scalars, .subsample = 3}), third);
  std::filesystem::remove(inr);
  std::filesystem::remove(vti);
}

TEST(ImageVolumeIo, SizeGuardNamesTheCountAndTheSubsampleThatFits) {
  const Grid g;  // 4 x 3 x 5 voxels: 6 * 3 * 2 * 4 = 144 tetrahedra; every 2nd: 6 * 1 * 1 * 2 = 12
  const std::string path = write_file("guard.inr", inr_bytes(g));
  expect_error(path, {.role = io::ArrayRole::Scalars, .max_cells = 100}, "144 tetrahedra, more than the limit of 100; --subsample 2");
  EXPECT_EQ(io::read_image_volume(path, {.role = io::ArrayRole::Scalars, .max_cells = 144}).tets.size(), 144u);
  // The guard reads the header only: a 2000^3 header with no voxels is refused for its size, not its
  // truncation. 6 * 1999^3 = 47928035994; every 6th voxel keeps 334 per axis, 6 * 333^3 > 2e8; every
  // 7th keeps 286, 6 * 285^3 = 138894750.
  const std::string huge = write_file("huge.inr", inr_header("XDIM=2000\nYDIM=2000\nZDIM=2000\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n"));
  expect_error(huge, {}, "47928035994 tetrahedra, more than the limit of 200000000; --subsample 7 (1 voxel in 7 per axis) makes 138894750");
  expect_error(path, {.role = io::ArrayRole::Scalars, .max_cells = 5}, "no subsampling fits");
  // Sizes whose product overflows 64 bits are refused, not wrapped around to a small count.
  const std::string absurd = write_file("absurd.inr", inr_header("XDIM=4000000000000\nYDIM=4000000000000\nZDIM=4000000000000\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\n"));
  expect_error(absurd, {}, "18446744073709551615 tetrahedra");
  std::filesystem::remove(path);
  std::filesystem::remove(huge);
  std::filesystem::remove(absurd);
}

// A compressed MetaImage whose zlib stream gives fewer bytes than the header declares (cut off,
// or a whole stream of too little data) is refused: MetaIO read it as an image whose missing
// voxels held whatever memory held, a different refusal (or none) from run to run. A good
// compressed file reads.
TEST(ImageVolumeIo, CompressedMetaImageThatInflatesShortIsRefused) {
  constexpr int n = 8;
  std::vector<float> voxels(n * n * n);
  for (size_t i = 0; i < voxels.size(); ++i) voxels[i] = float(i % 7);
  auto compressed = [](const std::vector<float>& v) {
    uLongf size = compressBound(uLong(v.size() * sizeof(float)));
    std::string out(size, '\0');
    EXPECT_EQ(compress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(v.data()), uLong(v.size() * sizeof(float))), Z_OK);
    out.resize(size);
    return out;
  };
  auto mha = [&](const std::string& name, const std::string& payload) {
    return write_file(name, "ObjectType = Image\nNDims = 3\nDimSize = 8 8 8\nElementType = MET_FLOAT\nElementSpacing = 1 1 1\n"
                            "CompressedData = True\nCompressedDataSize = " + std::to_string(payload.size()) +
                            "\nElementDataFile = LOCAL\n" + payload);
  };
  const io::ImageReadOptions scalars{.role = io::ArrayRole::Scalars};
  const std::string whole = compressed(voxels);
  const std::string good = mha("good.mha", whole);
  EXPECT_EQ(io::read_image_volume(good, scalars).points.size(), size_t(n * n * n));
  const std::string cut = mha("cut.mha", whole.substr(0, whole.size() / 2));
  expect_error(cut, scalars, "its compressed voxel data inflate to");
  const std::string few = mha("few.mha", compressed(std::vector<float>(voxels.begin(), voxels.begin() + 250)));
  expect_error(few, scalars, "inflate to 1000 bytes; the header declares 2048");
  for (const std::string& p : {good, cut, few}) std::filesystem::remove(p);
}

TEST(ImageVolumeIo, BadFilesNameTheFileAndTheProblem) {
  const Grid g;
  const std::string good = inr_bytes(g);
  const io::ImageReadOptions scalars{.role = io::ArrayRole::Scalars};
  expect_error(temp_path("missing.inr"), scalars, "does not exist");

  const std::string truncated = write_file("truncated.inr", good.substr(0, good.size() - 3));
  expect_error(truncated, scalars, "truncated");
  const std::string short_header = write_file("short.inr", good.substr(0, 100));
  expect_error(short_header, scalars, "truncated");
  const std::string extra = write_file("extra.inr", good + "xy");
  expect_error(extra, scalars, "bytes after");
  const std::string not_inr = write_file("not.inr", "P5 4 3 255\n" + good);
  expect_error(not_inr, scalars, "not an INRIMAGE-4 file");

  auto with = [&good](const std::string& from, const std::string& to) {
    std::string bytes = good;
    bytes.replace(bytes.find(from), from.size(), to);
    return bytes;
  };
  const std::string type = write_file("type.inr", with("TYPE=signed fixed", "TYPE=complex     "));
  expect_error(type, scalars, "TYPE=\"complex     \" is not supported");
  const std::string pixsize = write_file("pix.inr", with("PIXSIZE=16 bits", "PIXSIZE=12 bits"));
  expect_error(pixsize, scalars, "PIXSIZE");
  const std::string cpu = write_file("cpu.inr", with("CPU=sun", "CPU=vax"));
  expect_error(cpu, scalars, "CPU=\"vax\"");
  const std::string unknown = write_file("unknown.inr", with("#GEOMETRY", "COLOR=red\n#GEOM"));
  expect_error(unknown, scalars, "field COLOR is not understood");
  const std::string rotated = write_file("rotated.inr", with("#GEOMETRY", "RX=0.5\n#GEOM"));
  expect_error(rotated, scalars, "RX=0.5: rotated images are not supported");
  const std::string dims = write_file("dims.inr", with("XDIM=4", "XDIM=x"));
  expect_error(dims, scalars, "XDIM=x is not a positive integer");
  const std::string vector = write_file("vdim.inr", with("VDIM=1", "VDIM=3"));
  expect_error(vector, scalars, "VDIM=3");

  Grid flat = g;
  flat.dims[2] = 1;
  const std::string flat_path = write_file("flat.inr", inr_bytes(flat));
  expect_error(flat_path, scalars, "at least 2 voxels along each axis");

  const std::string vti = write_vti(g, "names.vti");
  expect_error(vti, {.array = "temperature"}, "no point array 'temperature' (point arrays: density, other)");
  const std::string garbage_vti = write_file("garbage.vti", "<VTKFile type=\"ImageData\"> nonsense");
  expect_error(garbage_vti, scalars, "VTK could not read");
  const std::string mhd = write_mhd(g, "short.mhd");
  std::filesystem::resize_file(temp_path("short.raw"), 10);
  expect_error(mhd, scalars, "data not read completely");
  const std::string inr_array = write_file("array.inr", good);
  expect_error(inr_array, {.array = "density"}, "one unnamed array");

  for (const std::string& p : {truncated, short_header, extra, not_inr, type, pixsize, cpu, unknown, rotated, dims, vector, flat_path, vti,
                               garbage_vti, inr_array, mhd, temp_path("short.raw")})
    std::filesystem::remove(p);
}

}  // namespace
}  // namespace prismoid
