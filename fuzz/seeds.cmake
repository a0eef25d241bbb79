# Seed corpora, written at configure time into the build tree (nothing binary is committed):
# small valid files of each format, so the fuzzers start from inputs that pass the first checks.
set(PRISMOID_SEEDS "${CMAKE_CURRENT_BINARY_DIR}/seeds")

function(prismoid_seed target name text)
  file(WRITE "${PRISMOID_SEEDS}/${target}/${name}" "${text}")
endfunction()

# INRIMAGE-4: the header is padded to 256 bytes in real files; the parser needs only the lines.
set(inr_header "#INRIMAGE-4#{\nXDIM=3\nYDIM=2\nZDIM=2\nVDIM=1\nTYPE=unsigned fixed\nPIXSIZE=8 bits\nSCALE=2**0\nCPU=decm\nVX=1\nVY=0.5\nVZ=2\n#GEOMETRY=CARTESIAN\n\n##}\n")
prismoid_seed(inrimage u8.inr "${inr_header}ABCDEFGHIJKL")
string(REPLACE "PIXSIZE=8 bits" "PIXSIZE=16 bits" inr16 "${inr_header}")
string(REPLACE "CPU=decm" "CPU=sun" inr16 "${inr16}")
prismoid_seed(inrimage u16-big.inr "${inr16}AABBCCDDEEFFGGHHIIJJKKLL")
string(REPLACE "TYPE=unsigned fixed" "TYPE=float" inrf "${inr_header}")
string(REPLACE "PIXSIZE=8 bits" "PIXSIZE=32 bits" inrf "${inrf}")
string(REPLACE "VZ=2\n" "VZ=2\nTX=1.5\nTY=-2\nTZ=0\n" inrf "${inrf}")
prismoid_seed(inrimage float.inr "${inrf}AAA@BBB@CCC@DDD@EEE@FFF@GGG@HHH@III@JJJ@KKK@LLL@")
# The same 8-bit image gzip-compressed, as CGAL ships its .inr.gz.
file(ARCHIVE_CREATE OUTPUT "${PRISMOID_SEEDS}/inrimage/u8.inr.gz" PATHS "${PRISMOID_SEEDS}/inrimage/u8.inr"
  FORMAT raw COMPRESSION GZip)

# OFF: a tetrahedron, a cube of quads with comments, an empty mesh.
prismoid_seed(off tet.off "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
prismoid_seed(off cube.off "OFF # a cube\n8 6 12\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n\n# faces\n4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3\n")
prismoid_seed(off empty.off "OFF\n0 0 0\n")

# ParaView colour maps: what File > Export writes, with and without opacity points.
prismoid_seed(colormap cool-warm.json "[{\"ColorSpace\": \"Diverging\", \"Name\": \"Cool to Warm\", \"RGBPoints\": [0, 0.23, 0.299, 0.754, 0.5, 0.865, 0.865, 0.865, 1, 0.706, 0.016, 0.15]}]\n")
prismoid_seed(colormap opacity.json "[{\"Name\": \"ramp\", \"RGBPoints\": [-2, 0, 0, 0, 3, 1, 1, 1], \"Points\": [-2, 0, 0.5, 0, 0.5, 0.25, 0.5, 0, 3, 1, 0.5, 0]}]\n")
prismoid_seed(colormap object.json "{\"Name\": \"one\", \"RGBPoints\": [0, 1, 0, 0]}\n")

# The structured targets decode bytes through FuzzedDataProvider: any bytes are a valid start.
prismoid_seed(tet_mesh a "tetrahedra: four points, one cell, extinction 1")
prismoid_seed(tet_mesh b "~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~")
prismoid_seed(voxel_tets a "a 3 x 4 x 5 image, subsample 1")
prismoid_seed(voxel_tets b "zzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzzz")

# Declared sizes: the first byte picks the kind (see fuzz_declared_sizes.cpp: "1" .ply, "2" .vtu, "5" .vtk, "6" .mha), then the file.
prismoid_seed(declared_sizes ply "1ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
prismoid_seed(declared_sizes vtu "2<VTKFile type=\"UnstructuredGrid\" compressor=\"vtkZLibDataCompressor\"><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\"><Points><DataArray type=\"Float32\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points></Piece></UnstructuredGrid></VTKFile>\n")
prismoid_seed(declared_sizes vtk "5# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n")
prismoid_seed(declared_sizes mha "6ObjectType = Image\nNDims = 3\nDimSize = 2 2 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\nABCD")
