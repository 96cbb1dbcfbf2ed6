// `rayscout diff A B`: error metrics between two images and an optional false-colour difference.
#include <array>
#include <cmath>
#include <string>

#include <fmt/core.h>

#include "commands.h"
#include "rayscout/core/file_extension.h"
#include "rayscout/core/input_error.h"
#include "rayscout/core/output_path.h"
#include "rayscout/image/image.h"

namespace rayscout::cli {
namespace {

struct DiffOptions {
  std::string a, b, out;
  float scale = 0;
  double max_rmse = -1;
};

CommandRegistration registration{[](CLI::App& app) {
  auto opts = std::make_shared<DiffOptions>();
  auto* cmd = app.add_subcommand("diff", "Compare image A with reference B: RMSE, relative MSE, PSNR, max error");
  set_memory_hint(*cmd, "compare smaller images");
  cmd->add_option("A", opts->a, "image (.png, .exr, .pfm)")->required()->check(file_path());
  cmd->add_option("B", opts->b, "reference image")->required()->check(file_path());
  cmd->add_option("--out", opts->out, "write a false-colour difference image (.png, .exr or .pfm)")
      ->check(output_file_path());
  add_number(*cmd, "--scale", opts->scale, "difference shown as red (0 = largest difference; NaN/inf pixels are red)",
             0.0f);
  cmd->add_option("--max-rmse", opts->max_rmse,
                  "exit with status 1 when the RMSE is above this (or NaN); not given: always exit 0")
      ->transform(in_range(0.0));
  cmd->callback([opts] {
    if (!opts->out.empty()) check_image_path(opts->out, 0, 0, "--out " + opts->out);  // before the work, not after it
    check_distinct_files(std::array{NamedFile{opts->out, "--out " + opts->out}},
                         std::array{NamedFile{opts->a, "image A " + opts->a}, NamedFile{opts->b, "reference B " + opts->b}});
    const Image a = read_image(opts->a), b = read_image(opts->b);
    // The same render as .png and as .pfm differed by an RMSE of 1.6 (its light, 17, became 1).
    const bool png_a = lower_extension(opts->a) == ".png", png_b = lower_extension(opts->b) == ".png";
    if (png_a != png_b)
      fmt::print(stderr,
                 "rayscout: warning: {} is a PNG (8-bit sRGB, clamped to [0, 1]) and {} is not: the metrics measure "
                 "the clamping too; compare .exr or .pfm images\n",
                 printable(png_a ? opts->a : opts->b), printable(png_a ? opts->b : opts->a));
    if (a.width != b.width || a.height != b.height)
      throw InputError(fmt::format("{} and {}: images differ in size: {}x{} vs {}x{}", opts->a, opts->b, a.width,
                                   a.height, b.width, b.height));
    const ImageError e = compare_images(a, b);
    fmt::print("rmse     {:.6g}\nrel_mse  {:.6g}\npsnr     {:.2f} dB\nmax_abs  {:.6g}\n", e.rmse, e.rel_mse, e.psnr,
               e.max_abs);
    if (e.nonfinite > 0) fmt::print("nonfinite {} channel values (NaN or inf) in the two images\n", e.nonfinite);
    if (!opts->out.empty()) {
      write_image(difference_image(a, b, opts->scale), opts->out);
      fmt::print("wrote {}\n", printable(opts->out));
    }
    if (opts->max_rmse >= 0 && !(e.rmse <= opts->max_rmse)) {  // a NaN RMSE fails too
      fmt::print("rmse {:.6g} is {} --max-rmse {:.6g}\n", e.rmse, std::isnan(e.rmse) ? "not a number: fails" : "above",
                 opts->max_rmse);
      throw CLI::RuntimeError(1);
    }
  });
}};

}  // namespace
}  // namespace rayscout::cli
