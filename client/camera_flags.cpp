#include "client/camera_flags.h"

#include "core/base/error.h"
#include "core/request/camera_text.h"

namespace tessera::cli {

namespace {

Vec3d parseVector(const std::string& text, const char* flag) {
  const std::optional<TypedVector> v = parseXyz(text);
  if (!v) throwInvalid(std::string("--") + flag + " expects X,Y,Z, got '" + text + "'");
  return {v->x, v->y, v->z};
}

void parseSize(const std::string& text, int& width, int& height) {
  const std::optional<TypedSize> size = parseWxH(text);
  if (!size) throwInvalid("--size expects WIDTHxHEIGHT, got '" + text + "'");
  width = size->width, height = size->height;
}

}  // namespace

void TessellateFlags::addTo(CLI::App& command) {
  command.add_option("model", model, "OBJ file, or meshes/NAME on a server")->required();
  command.add_option("-o,--output", output, "GLB file to write")->required();
  command.add_option("--tolerance", tolerance, "Tolerance (object units, or a fraction of the diagonal)");
  command.add_flag("--relative", relative, "Tolerance is a fraction of the bounding-box diagonal");
  command.add_option("--eta", eta, "Share of the tolerance for the Bezier approximation, in [0, 1); 0: single phase");
  command.add_option("--level", level, "Uniform tessellation level p (benchmark mode)");
  command.add_option("--eye", eye, "Camera position X,Y,Z (makes the tolerance pixel-accurate)");
  command.add_option("--target", target, "Camera target X,Y,Z");
  command.add_option("--up", up, "Camera up vector X,Y,Z");
  command.add_option("--fov", fov, "Vertical field of view in degrees");
  command.add_option("--size", size, "Viewport WIDTHxHEIGHT");
  command.add_option("--pixel-accuracy", pixelAccuracy, "Screen-space tolerance in pixels (default 0.5)");
  command.add_option("--max-triangles", maxTriangles, "Refuse requests past this many triangles");
  command.add_option("--encoding", encoding,
                     "GLB encoding: float (default), quantized (KHR_mesh_quantization, its error set aside from "
                     "the tolerance) or meshopt (that, compressed with EXT_meshopt_compression)");
}

TessellationOptions TessellateFlags::toOptions() const {
  TessellationOptions options;
  options.eta = eta;
  options.maxTriangles = maxTriangles;
  if (level == 0 && tolerance == 0 && eye.empty()) throwInvalid("give --tolerance, --level, or a camera (--eye/--target)");
  // A level decides alone; else a camera makes the accuracy pixels on its screen.
  if (level != 0) {
    options.accuracy = Accuracy::uniformLevel(level);
    validateAccuracy(options.accuracy, "--level");
  } else if (!eye.empty() || !target.empty()) {
    if (eye.empty() || target.empty()) throwInvalid("a camera needs both --eye and --target");
    Camera camera;
    camera.eye = parseVector(eye, "eye");
    camera.target = parseVector(target, "target");
    camera.up = parseVector(up, "up");
    camera.fovYDegrees = fov;
    parseSize(size, camera.width, camera.height);
    validateCamera(camera, "camera");
    options.accuracy = Accuracy::pixel(pixelAccuracy);
    validateAccuracy(options.accuracy, "--pixel-accuracy");
    options.camera = camera;
  } else {
    options.accuracy = relative ? Accuracy::relative(tolerance) : Accuracy::absolute(tolerance);
    validateAccuracy(options.accuracy, "--tolerance");
  }
  validateTessellationOptions(options);
  return options;
}

}  // namespace tessera::cli
