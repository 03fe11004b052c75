// SPDX-License-Identifier: MIT
// Report images of a finished (or running) run, read back from its series files on disk: front
// and rear views of every plate, with particles, scalar bar, scale bar and hole outlines.
#pragma once

#include "core/analysis/debris.hpp"
#include "core/analysis/hole_metrics.hpp"
#include "core/common/error.hpp"

#include <vtkSmartPointer.h>
#include <vtkType.h>

#include <string>
#include <vector>

class vtkActor;
class vtkDataObject;
class vtkLookupTable;
class vtkPolyData;
class vtkPolyDataMapper;
class vtkRenderer;
class vtkRenderWindow;
class vtkScalarsToColors;
class vtkUnstructuredGrid;

namespace fesph {

struct ImageOptions {
  int width = 1600, height = 1200;   ///< pixels
  /// Scalar cell array of elements_NNNNNN.vtu to colour by (damage, plastic_strain, von_mises,
  /// pressure, temperature, density, plastic_strain_rate).
  std::string field = "damage";
  bool particles = true;      ///< draw SPH particles as spheres of their radius
  bool hole_outlines = true;  ///< draw the through-holes found by findHoles on the rear view
};

/// Bodies of a run, in body order (the value of the "body" arrays).
struct RunBody {
  std::string name;
  bool projectile = false;
};
struct RunInfo {
  std::vector<RunBody> bodies;
  bool half = false;  ///< half model cut on y = 0 (scene: simulation.symmetry = "half")
};

/// Names from the header of RUN_DIR/history.csv; projectile flags and symmetry from
/// RUN_DIR/scene.toml (the copy `fesph run` writes). Missing files give what the other has.
RunInfo readRunInfo(const std::string& run_dir);

/// Images of one plate.
struct PlateImages {
  std::string plate;          ///< body name
  int body = -1;              ///< body index
  std::string front_png, rear_png;
  double time = 0;            ///< time of the series step drawn, s
  double pixel_size = 0;      ///< m per pixel in the plate's plane (the same for every plate)
  PlateHoles holes;           ///< through-holes of the plate at that time (full plate)
  /// A plate made of particles: its plate proper's particles (indices in that step's particle
  /// series), the plate rather than its debris. Empty for a plate of elements.
  std::vector<vtkIdType> particles;
};

/// A field the element series does not hold: the caller's bad input (`fesph render --field`
/// exits with 2 for it), not a failed run.
class UnknownField : public RunError {
 public:
  using RunError::RunError;
};

/// Front and rear orthographic views along the plate normal of every plate at the series step
/// nearest to `time` (time < 0: the last step), written to OUT_DIR/<plate>_front.png and
/// OUT_DIR/<plate>_rear.png. Plates: `plates` (body indices) or, when empty, every body that is
/// not a projectile. Half models are drawn mirrored (the full plate). All plates share one
/// camera extent. A plate made of particles (no element at that step) is drawn as its
/// particles, coloured by the field where the particle series has it, its holes found from
/// them (findParticleHoles); a plate with neither is not drawn: none such, an empty list.
/// Throws UnknownField, or RunError (no series, unwritable file).
std::vector<PlateImages> renderPlateImages(const std::string& run_dir, double time,
                                           const ImageOptions& options,
                                           const std::string& out_dir,
                                           const std::vector<int>& plates = {});

/// Building blocks shared by the render files (section view, plots).
namespace render_detail {

struct RunStep {
  double time = 0;  ///< s
  vtkSmartPointer<vtkUnstructuredGrid> elements;
  vtkSmartPointer<vtkPolyData> particles;  ///< null when the run has no particle series
};

/// The .vtu (and .vtp) of the step nearest to `time` (< 0: last). Throws RunError.
RunStep readRunStep(const std::string& run_dir, double time);
/// The .vtp of the step nearest to `time` (< 0: last); null when the run has no particle
/// series. Throws RunError.
vtkSmartPointer<vtkPolyData> readParticles(const std::string& run_dir, double time);

/// "52.3 µs" style label of a time in s.
std::string timeLabel(double time);

/// Name with units for a field's scalar bar, and the factor from SI to those units.
std::string fieldTitle(const std::string& field, double* scale);

/// Layout of a report image: a white page, the 3-D scene in the central viewport, title and
/// subtitle on top, a scale bar bottom left, a scalar bar on the right.
struct Page {
  vtkSmartPointer<vtkRenderer> scene;    ///< 3-D content, viewport kSceneViewport
  vtkSmartPointer<vtkRenderer> overlay;  ///< 2-D annotations, the whole window
  int width = 0, height = 0;
};
constexpr double kSceneViewport[4] = {0.02, 0.08, 0.84, 0.90};  // xmin ymin xmax ymax
/// Adds the two renderers to `window` (overlay first, so the scene is drawn over it).
Page makePage(vtkRenderWindow* window, int width, int height);

/// A mapper colouring `skin` by its cell array "shown" through `lut` (fixed range).
vtkSmartPointer<vtkPolyDataMapper> fieldMapper(vtkPolyData* skin, vtkLookupTable* lut);
void addTitle(Page& page, const std::string& title, const std::string& subtitle);
/// Scale bar for `pixel_size` m per pixel, a round length near a fifth of the scene width.
void addScaleBar(Page& page, double pixel_size);
/// Round [lo, hi] outwards to whole label steps (1, 2, 2.5 or 5 x 10^k, four to six
/// intervals) so the scalar bar reads in round numbers. Returns the number of labels.
int niceRange(double& lo, double& hi);
/// Scalar bar for `lut` with `title` and `labels` labels over the table's range.
void addScalarBar(Page& page, vtkScalarsToColors* lut, const std::string& title, int labels);
/// Viridis lookup table over [lo, hi].
vtkSmartPointer<vtkLookupTable> viridis(double lo, double hi);
/// The colours of `field`: viridis over [lo, hi]; for "material", one colour per entry of the
/// series' field data `material_names` (of `data`), named in a legend (addScalarBar).
vtkSmartPointer<vtkLookupTable> fieldColours(const std::string& field, double lo, double hi,
                                             vtkDataObject* data);
/// Colour of body `b` for particles (a categorical palette distinct from viridis).
void bodyColour(int b, double rgb[3]);
/// The particles of body `body` in a step's particle series (none without a series).
std::vector<vtkIdType> particlesOf(vtkPolyData* particles, int body);
/// Those particles as findParticleHoles takes them. Throws RunError without their radius
/// and mass.
std::vector<DebrisParticle> plateParticles(vtkPolyData* particles,
                                           const std::vector<vtkIdType>& ids);

/// Particles `keep` selects drawn as spheres of their "radius": coloured by `field` (times
/// `unit`, the lookup table's units: fieldTitle) through `lut`, or by body (bodyColour) when
/// `lut` is null or the particle series has no such field; `mirror_y` adds their mirror images
/// on y = 0 (half models). Null when none is kept.
vtkSmartPointer<vtkActor> particleActor(vtkPolyData* particles,
                                        const std::vector<vtkIdType>& keep,
                                        vtkScalarsToColors* lut, const std::string& field,
                                        double unit, bool mirror_y = false);

}  // namespace render_detail

}  // namespace fesph
