// core/obj_reader: every shipped model and OpenSubdiv shape against MODELS-STATS.csv, the shapes
// Tessera refuses, and hand-written OBJ text for each form the format allows.
#include "core/mesh/obj_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "core/base/error.h"
#include "tests/support/model_stats.h"

namespace tessera {
namespace {

using testing::modelsDir;
using testing::ModelStats;
using testing::readModelStats;

// A shape Tessera refuses, with the start of the line to blame and what the message must say.
struct RefusedShape {
  const char* file;
  ErrorKind kind;
  const char* lineStart;
  const char* reason;
};

const RefusedShape kRefusedShapes[] = {
    {"opensubdiv-shapes/catmark_square_hedit0.obj", ErrorKind::kUnsupported, "t vertexedit",
     "'t vertexedit' (hierarchical edit)"},
    {"opensubdiv-shapes/catmark_square_hedit1.obj", ErrorKind::kUnsupported, "t vertexedit",
     "'t vertexedit' (hierarchical edit)"},
    {"opensubdiv-shapes/catmark_square_hedit2.obj", ErrorKind::kUnsupported, "t vertexedit",
     "'t vertexedit' (hierarchical edit)"},
    {"opensubdiv-shapes/catmark_square_hedit3.obj", ErrorKind::kUnsupported, "t vertexedit",
     "'t vertexedit' (hierarchical edit)"},
    {"opensubdiv-shapes/catmark_square_hedit4.obj", ErrorKind::kUnsupported, "t vertexedit",
     "'t vertexedit' (hierarchical edit)"},
};

bool isRefused(const std::string& file) {
  return std::any_of(std::begin(kRefusedShapes), std::end(kRefusedShapes),
                     [&](const RefusedShape& shape) { return file == shape.file; });
}

// The 1-based number of the first line that starts with `start`, found without the reader.
int firstLineStartingWith(const std::string& path, const std::string& start) {
  std::ifstream in(path);
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    if (line.rfind(start, 0) == 0) return number;
  }
  return -1;
}

std::map<int, int> faceSizeHistogram(const ControlMesh& mesh) {
  std::map<int, int> histogram;
  for (int size : mesh.faceSizes) ++histogram[size];
  return histogram;
}

int tagLines(const ModelStats& stats, const std::string& tag) {
  const auto found = stats.tagLines.find(tag);
  return found == stats.tagLines.end() ? 0 : found->second;
}

// Expects readObj to refuse `text` with `kind` and a message containing `part`.
void expectRefused(const std::string& text, ErrorKind kind, const std::string& part) {
  try {
    readObj(text, "test.obj");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), kind) << error.what();
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos)
        << "message: " << error.what() << "\nexpected to contain: " << part;
  }
}

const char* const kSquare =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n"
    "f 1 2 3 4\n";

TEST(ObjReader, EveryModelMatchesTheStatsTable) {
  const std::vector<ModelStats> models = readModelStats();
  ASSERT_GT(models.size(), 80u);
  for (const ModelStats& stats : models) {
    if (isRefused(stats.file)) continue;
    SCOPED_TRACE(stats.file);
    const ControlMesh mesh = readObjFile(modelsDir() + "/" + stats.file);
    EXPECT_EQ(mesh.vertexCount(), stats.vertices);
    EXPECT_EQ(mesh.faceCount(), stats.faces);
    EXPECT_EQ(faceSizeHistogram(mesh), stats.faceSizeHistogram);
    // Every crease and corner tag in these files names a single edge or vertex.
    EXPECT_EQ(static_cast<int>(mesh.creases.size()), tagLines(stats, "crease"));
    EXPECT_EQ(static_cast<int>(mesh.corners.size()), tagLines(stats, "corner"));
    EXPECT_EQ(mesh.holes.empty(), tagLines(stats, "hole") == 0);
  }
}

TEST(ObjReader, EveryModelFileIsInTheStatsTable) {
  std::set<std::string> listed;
  for (const ModelStats& stats : readModelStats()) listed.insert(stats.file);
  int files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(modelsDir())) {
    if (entry.path().extension() != ".obj") continue;
    ++files;
    const std::string relative =
        std::filesystem::relative(entry.path(), modelsDir()).generic_string();
    EXPECT_TRUE(listed.count(relative)) << relative << " is not in MODELS-STATS.csv";
  }
  EXPECT_EQ(files, static_cast<int>(listed.size()));
}

TEST(ObjReader, RefusedShapesNameTheTagAndItsLine) {
  for (const RefusedShape& shape : kRefusedShapes) {
    SCOPED_TRACE(shape.file);
    const std::string path = modelsDir() + "/" + shape.file;
    const int line = firstLineStartingWith(path, shape.lineStart);
    ASSERT_GT(line, 0);
    try {
      readObjFile(path);
      ADD_FAILURE() << "accepted";
    } catch (const TesseraError& error) {
      EXPECT_EQ(error.kind(), shape.kind);
      const std::string expected = path + ":" + std::to_string(line) + ": " + shape.reason;
      EXPECT_EQ(std::string(error.what()).rfind(expected, 0), 0u)
          << "message: " << error.what() << "\nexpected to start with: " << expected;
    }
  }
}

TEST(ObjReader, InterpolateBoundaryFollowsOpenSubdivShapeNumbering) {
  const std::string shapes = modelsDir() + "/opensubdiv-shapes/";
  EXPECT_EQ(readObjFile(shapes + "catmark_edgecorner.obj").rules.boundary,
            BoundaryInterpolation::kEdgeAndCorner);
  EXPECT_EQ(readObjFile(shapes + "catmark_dart_edgecorner.obj").rules.boundary,
            BoundaryInterpolation::kEdgeAndCorner);
  EXPECT_EQ(readObjFile(shapes + "catmark_edgeonly.obj").rules.boundary,
            BoundaryInterpolation::kEdgeOnly);
  EXPECT_EQ(readObjFile(shapes + "catmark_cube.obj").rules.boundary, BoundaryInterpolation::kEdgeOnly);
  EXPECT_EQ(readObj(std::string(kSquare) + "t interpolateboundary 1/0/0 1\n", "s").rules.boundary,
            BoundaryInterpolation::kEdgeAndCorner);
  EXPECT_EQ(readObj(std::string(kSquare) + "t interpolateboundary 1/0/0 2\n", "s").rules.boundary,
            BoundaryInterpolation::kEdgeOnly);
}

TEST(ObjReader, CreaseSharpnessAndHolesAreReadAsWritten) {
  const std::string shapes = modelsDir() + "/opensubdiv-shapes/";
  const ControlMesh cube = readObjFile(shapes + "catmark_cube_creases1.obj");
  ASSERT_EQ(cube.creases.size(), 12u);
  EXPECT_EQ(cube.creases.front().v0, 0);
  EXPECT_EQ(cube.creases.front().v1, 1);
  EXPECT_FLOAT_EQ(cube.creases.front().sharpness, 5.0f);
  EXPECT_EQ(cube.creases.back().v0, 3);
  EXPECT_EQ(cube.creases.back().v1, 5);
  EXPECT_FLOAT_EQ(cube.creases.back().sharpness, 0.1f);
  EXPECT_EQ(readObjFile(shapes + "catmark_hole_test1.obj").holes, std::vector<int>({1}));
  EXPECT_EQ(readObjFile(shapes + "catmark_hole_test2.obj").holes, std::vector<int>({5, 6, 9, 10}));
}

TEST(ObjReader, NegativeIndicesCountBackFromTheLastVertexRead) {
  const ControlMesh mesh =
      readObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\nv 0 1 0\nf -4 -2 -1\n", "relative.obj");
  EXPECT_EQ(mesh.faceSizes, std::vector<int>({3, 3}));
  EXPECT_EQ(mesh.faceVertices, std::vector<int>({0, 1, 2, 0, 2, 3}));
}

TEST(ObjReader, EveryFaceVertexFormGivesTheSameFace) {
  const std::string vertices = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
  for (const char* face : {"f 1 2 3", "f 1/1 2/2 3/3", "f 1//1 2//1 3//1", "f 1/1/1 2/2/1 3/3/1",
                           "f -3/-3/-1 -2/-2/-1 -1/-1/-1"}) {
    SCOPED_TRACE(face);
    const ControlMesh mesh = readObj(vertices + face + "\n", "forms.obj");
    EXPECT_EQ(mesh.faceVertices, std::vector<int>({0, 1, 2}));
  }
  for (const char* face : {"f 1/ 2 3", "f 1/1/ 2 3", "f 1/1/1/1 2 3", "f 1//x 2 3", "f / 2 3"}) {
    expectRefused(vertices + face + "\n", ErrorKind::kInvalidInput, "test.obj:8: bad face vertex");
  }
}

TEST(ObjReader, CrlfReadsLikeLf) {
  const std::string lf = "# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\nf 1 2 3 4\n";
  std::string crlf;
  for (char c : lf) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const ControlMesh a = readObj(lf, "lf.obj"), b = readObj(crlf, "crlf.obj");
  EXPECT_EQ(a.faceVertices, b.faceVertices);
  EXPECT_EQ(a.vertexCount(), b.vertexCount());
  expectRefused(crlf + "v 1 2\r\n", ErrorKind::kInvalidInput, "test.obj:8: missing z coordinate");
}

TEST(ObjReader, ByteOrderMarkIsSkippedOnlyAtTheStart) {
  EXPECT_EQ(readObj(std::string("\xEF\xBB\xBF") + kSquare, "bom.obj").faceCount(), 1);
  expectRefused(std::string(kSquare) + "\xEF\xBB\xBFv 1 1 1\n", ErrorKind::kInvalidInput,
                "test.obj:6: unknown OBJ statement '\\xef\\xbb\\xbfv'");
}

TEST(ObjReader, NumbersTakeSignsExponentsAndAnIgnoredW) {
  const ControlMesh mesh =
      readObj("v +1 -2.5e1 3E-2 0.5\nv 1e-50 0 0\nv 0 1 0\nf 1 2 3\n", "numbers.obj");
  EXPECT_FLOAT_EQ(mesh.positions[0].x, 1.0f);
  EXPECT_FLOAT_EQ(mesh.positions[0].y, -25.0f);
  EXPECT_FLOAT_EQ(mesh.positions[0].z, 0.03f);
  EXPECT_EQ(mesh.positions[1].x, 0.0f);  // below float's range: rounds to zero, not an error
}

TEST(ObjReader, SkipsCommentsGroupsMaterialsAndBlankLines) {
  const ControlMesh mesh = readObj(
      "# header\nmtllib a.mtl\no square\ng group one\ns 1\nusemtl red\n\n   \t\n"
      "v 0 0 0 # trailing comment\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.5 0.5\nvn 0 0 1\n"
      "s off\nf 1 2 3 4 # quad\n",
      "skips.obj");
  EXPECT_EQ(mesh.vertexCount(), 4);
  EXPECT_EQ(mesh.faceSizes, std::vector<int>({4}));
}

TEST(ObjReader, FacesMayNameVerticesDefinedLater) {
  const ControlMesh mesh = readObj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "later.obj");
  EXPECT_EQ(mesh.faceVertices, std::vector<int>({0, 1, 2}));
  expectRefused("f 1 2 4\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", ErrorKind::kInvalidInput,
                "test.obj:1: face vertex index 4 is out of range: the file has 3 vertices");
}

TEST(ObjReader, CreaseTagsListVertexPairsWithOneOrPerPairSharpness) {
  const std::string grid =
      "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n";
  const ControlMesh shared = readObj(grid + "t crease 4/1/0 0 1 1 4 2.5\n", "shared.obj");
  ASSERT_EQ(shared.creases.size(), 2u);
  EXPECT_EQ(shared.creases[1].v0, 1);
  EXPECT_EQ(shared.creases[1].v1, 4);
  EXPECT_FLOAT_EQ(shared.creases[1].sharpness, 2.5f);
  const ControlMesh each = readObj(grid + "t crease 4/2/0 0 1 4 1 1 10\n", "each.obj");
  ASSERT_EQ(each.creases.size(), 2u);
  EXPECT_FLOAT_EQ(each.creases[0].sharpness, 1.0f);
  EXPECT_FLOAT_EQ(each.creases[1].sharpness, kInfiniteSharpness);
  expectRefused(grid + "t crease 4/3/0 0 1 1 4 1 2 3\n", ErrorKind::kInvalidInput,
                "'t crease' expects pairs of vertex ids");
}

TEST(ObjReader, CornersAndHolesAreRead) {
  const ControlMesh mesh = readObj(std::string(kSquare) + kSquare +
                                       "t corner 2/1/0 0 2 3.5\nt corner 2/2/0 1 3 1 2\n"
                                       "t hole 1/0/0 1\n",
                                   "tags.obj");
  ASSERT_EQ(mesh.corners.size(), 4u);
  EXPECT_EQ(mesh.corners[1].vertex, 2);
  EXPECT_FLOAT_EQ(mesh.corners[1].sharpness, 3.5f);
  EXPECT_EQ(mesh.corners[3].vertex, 3);
  EXPECT_FLOAT_EQ(mesh.corners[3].sharpness, 2.0f);
  EXPECT_EQ(mesh.holes, std::vector<int>({1}));
}

TEST(ObjReader, TagsThatKeepTheSurfaceAreAccepted) {
  for (const char* tag :
       {"t creasemethod 0/0/1 normal", "t creasemethod 0/0/1 uniform",
        "t smoothtriangles 0/0/1 catmark", "t facevaryinginterpolateboundary 1/0/0 3"}) {
    SCOPED_TRACE(tag);
    const ControlMesh mesh = readObj(std::string(kSquare) + tag + "\n", "kept.obj");
    EXPECT_EQ(mesh.faceCount(), 1);
    EXPECT_EQ(mesh.rules, SubdivisionRules{});
  }
}

TEST(ObjReader, ErrorsStartWithSourceAndLine) {
  expectRefused("v 0 0 0\nv 1 0 0\nv 0 1 zero\nf 1 2 3\n", ErrorKind::kInvalidInput,
                "test.obj:3: bad z coordinate 'zero'");
  try {
    readObj("v 0 0 0\n\nf 1 2\n", "named.obj");
    FAIL() << "accepted";
  } catch (const TesseraError& error) {
    EXPECT_EQ(std::string(error.what()).rfind("named.obj:3: ", 0), 0u) << error.what();
  }
}

TEST(ObjReader, LimitsStopReadingAtTheLineThatCrossesThem) {
  MeshLimits limits;
  limits.maxVertices = 3;
  limits.maxFaces = 1;
  limits.maxFaceSize = 4;
  limits.maxAbsCoordinate = 100.0f;
  const auto kindAndMessage = [&](const std::string& text) {
    try {
      readObj(text, "limits.obj", limits);
    } catch (const TesseraError& error) {
      return std::make_pair(error.kind(), std::string(error.what()));
    }
    return std::make_pair(ErrorKind::kInvalidInput, std::string("accepted"));
  };
  const std::string triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_EQ(kindAndMessage(triangle + "v 1 1 0\n"),
            std::make_pair(ErrorKind::kLimitExceeded,
                           std::string("limits.obj:4: more than 3 vertices (the limit)")));
  EXPECT_EQ(kindAndMessage(triangle + "f 1 2 3\nf 3 2 1\n"),
            std::make_pair(ErrorKind::kLimitExceeded,
                           std::string("limits.obj:5: more than 1 faces (the limit)")));
  EXPECT_EQ(kindAndMessage(triangle + "f 1 2 3 -1 -2\n").first, ErrorKind::kLimitExceeded);
  EXPECT_EQ(kindAndMessage("v 0 0 101\n").first, ErrorKind::kLimitExceeded);
}

TEST(ObjReader, MissingFileIsReported) {
  try {
    readObjFile("/nonexistent/tessera/mesh.obj");
    FAIL() << "accepted";
  } catch (const TesseraError& error) {
    EXPECT_EQ(error.kind(), ErrorKind::kInvalidInput);
    EXPECT_NE(std::string(error.what()).find("/nonexistent/tessera/mesh.obj"), std::string::npos);
  }
  EXPECT_THROW(readObjFile(modelsDir()), TesseraError);  // a directory
}

}  // namespace
}  // namespace tessera
