/// granular-gui: steers a run live in a window (GLFW, OpenGL 3.3 core, Dear ImGui). The 3-D view
/// is drawn by the renderer of the headless figures (render::ParticleRenderer) into the window's
/// framebuffer; the simulation runs on its own thread (SimRunner) and the window draws whole
/// snapshots of it. `--script` presses the buttons from the command line (gui_script.hpp).
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <future>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "controls_layout.hpp"
#include "figure_export.hpp"
#include "granular/render/colormap.hpp"
#include "granular/render/font.hpp"
#include "granular/render/image.hpp"
#include "granular/render/particle_view.hpp"
#include "gui_options.hpp"
#include "gui_script.hpp"
#include "orbit_camera.hpp"
#include "sim_runner.hpp"
#include "status_line.hpp"
#include "wall_drawing.hpp"

namespace fs = std::filesystem;
using namespace granular;
using namespace granular::gui;

namespace {

/// The few GL calls the window itself makes (the renderer and ImGui load their own).
struct WindowGl {
  void (*viewport)(int, int, int, int);
  void (*scissor)(int, int, int, int);
  void (*enable)(unsigned);
  void (*disable)(unsigned);
  void (*clearColor)(float, float, float, float);
  void (*clear)(unsigned);
  void (*readPixels)(int, int, int, int, unsigned, unsigned, void*);
  void (*pixelStorei)(unsigned, int);
};
constexpr unsigned kScissorTest = 0x0C11, kColorBufferBit = 0x4000, kDepthBufferBit = 0x0100,
                   kRgba = 0x1908, kUnsignedByte = 0x1401, kPackAlignment = 0x0D05;

template <class F>
void load(F& f, const char* name) {
  f = reinterpret_cast<F>(glfwGetProcAddress(name));
  if (!f) throw std::runtime_error(std::string("OpenGL entry point missing: ") + name);
}

WindowGl loadWindowGl() {
  WindowGl gl{};
  load(gl.viewport, "glViewport");
  load(gl.scissor, "glScissor");
  load(gl.enable, "glEnable");
  load(gl.disable, "glDisable");
  load(gl.clearColor, "glClearColor");
  load(gl.clear, "glClear");
  load(gl.readPixels, "glReadPixels");
  load(gl.pixelStorei, "glPixelStorei");
  return gl;
}

enum class Colouring { Force, Speed, Stress, None };

/// Everything the panels edit, kept between frames.
struct UiState {
  Colouring colouring = Colouring::Force;
  OrbitCamera orbit;
  int sceneChoice = 1;
  char checkpoint[256] = "granular-gui.ckpt";
  char exportPath[256] = "granular-gui-view.png";
  char sceneFile[512] = "";
  char figureFolder[256] = "granular-gui-figures";
  std::future<std::string> figureExport;  ///< running on a worker thread: its own GL context
  std::string figureMessage;
  fs::path screenshotRequest;  ///< written after this frame is drawn
  fs::path viewRequest;        ///< the 3-D view alone, drawn anew at 2× the screen's size
  Material material;           ///< being edited
  double topWallVelocity = 0;
  int integrator = 0;  ///< 0 Gear5, 1 Verlet
  bool automaticStep = false;
  double timeStep = 0;
  int stepsPerUpdate = 20;
  bool synced = false;                        ///< edits initialised from the run
  std::set<std::string> cutOffLabels;         ///< labels that ran past the panel's edge in a frame
  std::set<std::string> labelsWithoutGlyphs;  ///< labels with a character the font lacks
};

const char* kScenes[] = {"paper-mu0.toml", "paper-mu03.toml", "demo.toml"};

/// Draws the figures of a copy of `snap` on a worker thread (figure_export.hpp: the headless
/// context must not meet the window's on one thread); the message says where they went.
void startFigureExport(UiState& ui, const Snapshot& snap) {
  ui.figureMessage = "exporting figures...";
  ui.figureExport = std::async(std::launch::async, [snap, folder = fs::path(ui.figureFolder)] {
    try {
      const std::vector<fs::path> files = exportFigures(snap, folder);
      return std::to_string(files.size()) + " figures in " + folder.string();
    } catch (const std::exception& e) {
      return std::string("figures not exported: ") + e.what();
    }
  });
}

/// ImGui's own font has no Greek: the parameters' symbols (μ, ν, γn) would show as '?'. Their
/// glyphs are merged in from DejaVu Sans, the figures' font, where it is installed.
void addGreekGlyphs() {
  ImGuiIO& io = ImGui::GetIO();
  io.Fonts->AddFontDefault();
  const fs::path file = render::Font::file(render::FontWeight::Regular);
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return;
  static const ImWchar kGreek[] = {0x0370, 0x03FF, 0};
  ImFontConfig merge;
  merge.MergeMode = true;
  io.Fonts->AddFontFromFileTTF(file.c_str(), 13.0f, &merge, kGreek);
}

/// The label of a material parameter's field: key, symbol and unit ("youngs_modulus E [Pa]").
std::string materialLabel(const ParameterSpec& p) {
  return std::string(p.key) + " " + std::string(p.symbol) +
         (p.unit == "-" ? std::string() : " [" + std::string(p.unit) + "]");
}

/// Every label the controls panel draws beside a field (the density is not offered: the
/// particles' masses fix it).
std::vector<std::string> fieldLabels() {
  std::vector<std::string> labels = {"steps/update", "top wall v [m/s]", "integrator", "dt [s]"};
  for (const ParameterSpec& p : materialParameters()) {
    if (p.term != Body::name) labels.push_back(materialLabel(p));
  }
  return labels;
}

/// The controls panel at least 340 px wide, its fields at least 130 px (a scene's name in the
/// combo), and wide enough for the widest label beside a field, as the current font draws it.
ControlsLayout currentControlsLayout() {
  const ImGuiStyle& style = ImGui::GetStyle();
  float widest = 0;
  for (const std::string& label : fieldLabels()) {
    widest = std::max(widest, ImGui::CalcTextSize(label.c_str()).x);
  }
  return controlsLayout(widest, 130, 340,
                        {style.WindowPadding.x, style.ItemInnerSpacing.x, style.ScrollbarSize});
}

/// The labels beside fields with a character the current font has no glyph for (drawn as '?').
std::set<std::string> labelsWithoutGlyphs() {
  std::set<std::string> found;
  for (const std::string& label : fieldLabels()) {
    for (const char32_t c : render::decodeUtf8(label)) {
      if (c > 0xFFFF || !ImGui::GetFont()->FindGlyphNoFallback(ImWchar(c))) found.insert(label);
    }
  }
  return found;
}

/// Notes `label` when the widget just drawn (its field and the label beside it) runs past the
/// panel's content edge, where ImGui cuts it off.
void noteIfCutOff(UiState& ui, const std::string& label) {
  const float edge = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
  if (ImGui::GetItemRectMax().x > edge + 0.5f) ui.cutOffLabels.insert(label);
}

void controlsPanel(SimRunner& runner, const Snapshot& snap, UiState& ui,
                   const ControlsLayout& layout, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(layout.panelWidth, height));
  ImGui::Begin("Controls", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_AlwaysVerticalScrollbar);
  ImGui::PushItemWidth(layout.fieldWidth);
  if (!ui.synced) {
    ui.material = snap.material;
    ui.topWallVelocity = snap.topWallVelocity;
    ui.integrator = snap.integrator == Integrator::Gear5 ? 0 : 1;
    ui.timeStep = snap.timeStep;
    ui.automaticStep = snap.automaticStep;
    ui.stepsPerUpdate = snap.stepsPerUpdate;
    ui.synced = true;
  }
  ImGui::TextWrapped("Scene: %s", fs::path(snap.sceneFile).filename().c_str());
  // Fields without a label take the line, up to the button beside them.
  const float besideButton = ImGui::CalcTextSize("Load file").x +
                             2 * ImGui::GetStyle().FramePadding.x + ImGui::GetStyle().ItemSpacing.x;
  ImGui::SetNextItemWidth(-besideButton);
  ImGui::Combo("##scene", &ui.sceneChoice, kScenes, IM_ARRAYSIZE(kScenes));
  ImGui::SameLine();
  if (ImGui::Button("Load")) {
    runner.loadScene(fs::path(GRANULAR_SCENES_DIR) / kScenes[ui.sceneChoice]);
    ui.synced = false;
  }
  ImGui::SetNextItemWidth(-besideButton);
  ImGui::InputTextWithHint("##file", "or a scene file path", ui.sceneFile, sizeof ui.sceneFile);
  ImGui::SameLine();
  if (ImGui::Button("Load file") && ui.sceneFile[0]) {
    runner.loadScene(ui.sceneFile);
    ui.synced = false;
  }
  ImGui::Separator();
  if (ImGui::Button(snap.running ? "Pause" : "Run", ImVec2(70, 0))) {
    snap.running ? runner.pause() : runner.run();
  }
  ImGui::SameLine();
  if (ImGui::Button("Step")) runner.step(1);
  ImGui::SameLine();
  if (ImGui::Button("Reset")) {
    runner.reset();
    ui.synced = false;
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(snap.stage == 2);
  if (ImGui::Button("Stage 2")) runner.startStage2();
  ImGui::EndDisabled();
  if (ImGui::SliderInt("steps/update", &ui.stepsPerUpdate, 1, 500)) {
    runner.setStepsPerUpdate(ui.stepsPerUpdate);
  }
  noteIfCutOff(ui, "steps/update");
  ImGui::Separator();
  ImGui::Text("Material (applied on Enter)");
  bool edited = false;
  // One field per parameter the contact model declares (the bodies' density is fixed by the
  // particles' masses, so it is not offered).
  for (const ParameterSpec& p : materialParameters()) {
    if (p.term == Body::name) continue;
    const std::string label = materialLabel(p);
    double value = p.get(ui.material);
    if (p.kind == ParameterKind::Number) {
      ImGui::InputDouble(label.c_str(), &value, 0.0, 0.0, "%.4g");
      edited |= ImGui::IsItemDeactivatedAfterEdit();
    } else if (p.kind == ParameterKind::Flag) {
      bool on = value != 0.0;
      edited |= ImGui::Checkbox(label.c_str(), &on);
      value = on ? 1.0 : 0.0;
    } else {
      int at = static_cast<int>(value);
      std::vector<const char*> names;
      std::vector<std::string> storage(p.names.begin(), p.names.end());
      for (const std::string& n : storage) names.push_back(n.c_str());
      edited |= ImGui::Combo(label.c_str(), &at, names.data(), int(names.size()));
      value = at;
    }
    noteIfCutOff(ui, label);
    p.set(ui.material, value);
  }
  if (edited) runner.setMaterial(ui.material);
  ImGui::InputDouble("top wall v [m/s]", &ui.topWallVelocity, 0.0, 0.0, "%.4f");
  noteIfCutOff(ui, "top wall v [m/s]");
  if (ImGui::IsItemDeactivatedAfterEdit()) runner.setTopWallVelocity(ui.topWallVelocity);
  ImGui::Separator();
  const char* integrators[] = {"gear5", "verlet"};
  ImGui::Combo("integrator", &ui.integrator, integrators, 2);
  noteIfCutOff(ui, "integrator");
  ImGui::Checkbox("dt auto", &ui.automaticStep);
  if (!ui.automaticStep) {
    ImGui::InputDouble("dt [s]", &ui.timeStep, 0.0, 0.0, "%.3e");
    noteIfCutOff(ui, "dt [s]");
  }
  if (snap.automaticStep) {
    ImGui::Text("dt %.3e s (%.3e to %.3e so far)", snap.timeStep, snap.smallestStep,
                snap.largestStep);
  }
  ImGui::Text("network allows %.3e s", snap.maxTimeStep);
  if (ImGui::Button("Apply integrator")) {
    runner.setIntegrator(ui.integrator == 0 ? Integrator::Gear5 : Integrator::VelocityVerlet,
                         ui.timeStep, ui.automaticStep);
  }
  ImGui::Separator();
  ImGui::Text("Colour by");
  int colouring = int(ui.colouring);
  ImGui::RadioButton("sum |F|", &colouring, 0);
  ImGui::SameLine();
  ImGui::RadioButton("speed", &colouring, 1);
  ImGui::SameLine();
  ImGui::RadioButton("sigma33", &colouring, 2);
  ImGui::SameLine();
  ImGui::RadioButton("none", &colouring, 3);
  ui.colouring = Colouring(colouring);
  if (ImGui::Button("Reset view")) ui.orbit.reset();
  ImGui::TextDisabled("drag: orbit, right drag: pan, wheel: zoom");
  ImGui::Separator();
  ImGui::SetNextItemWidth(-FLT_MIN);
  ImGui::InputText("##ckpt", ui.checkpoint, sizeof ui.checkpoint);
  if (ImGui::Button("Save checkpoint")) runner.saveCheckpoint(ui.checkpoint);
  ImGui::SameLine();
  if (ImGui::Button("Load checkpoint")) {
    runner.loadCheckpoint(ui.checkpoint);
    ui.synced = false;
  }
  ImGui::SetNextItemWidth(-FLT_MIN);
  ImGui::InputText("##png", ui.exportPath, sizeof ui.exportPath);
  if (ImGui::Button("Save window")) ui.screenshotRequest = ui.exportPath;
  ImGui::SameLine();
  if (ImGui::Button("Save 3-D view")) ui.viewRequest = ui.exportPath;
  ImGui::SetNextItemWidth(-FLT_MIN);
  ImGui::InputText("##figures", ui.figureFolder, sizeof ui.figureFolder);
  ImGui::BeginDisabled(ui.figureExport.valid());
  if (ImGui::Button("Export figures")) startFigureExport(ui, snap);
  ImGui::EndDisabled();
  if (ui.figureExport.valid() &&
      ui.figureExport.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
    ui.figureMessage = ui.figureExport.get();
  }
  if (!ui.figureMessage.empty()) ImGui::TextWrapped("%s", ui.figureMessage.c_str());
  ImGui::PopItemWidth();
  ImGui::End();
}

void plotsPanel(const Snapshot& snap, float x, float y, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(x, y));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin("Live plots", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  const LiveSeries& s = snap.series;
  struct Plot {
    const char* title;
    const std::vector<float>* values;
  };
  const Plot plots[] = {
      {"kinetic energy [J]", &s.kinetic}, {"sigma33 Eq.(1) [Pa]", &s.eq1[2]},
      {"sigma33 Eq.(2) [Pa]", &s.eq2[2]}, {"R33 bottom [N]", &s.bottomForce},
      {"sigma11 Eq.(1) [Pa]", &s.eq1[0]}, {"sigma11 Eq.(2) [Pa]", &s.eq2[0]},
      {"sigma22 Eq.(2) [Pa]", &s.eq2[1]}, {"R33 top [N]", &s.topForce},
  };
  const int columns = 4;
  const float plotWidth = (width - 20) / columns - 8;
  const float plotHeight = (height - 50) / 2 - 22;
  for (int k = 0; k < 8; ++k) {
    if (k % columns) ImGui::SameLine();
    ImGui::BeginGroup();
    const std::vector<float>& v = *plots[k].values;
    char overlay[64] = "";
    if (!v.empty()) std::snprintf(overlay, sizeof overlay, "%.4g", double(v.back()));
    if (v.empty() && !s.time.empty()) std::snprintf(overlay, sizeof overlay, "no box walls");
    ImGui::TextUnformatted(plots[k].title);
    ImGui::PushID(k);
    ImGui::PlotLines("##plot", v.data(), int(v.size()), 0, overlay, FLT_MAX, FLT_MAX,
                     ImVec2(plotWidth, plotHeight));
    ImGui::PopID();
    ImGui::EndGroup();
  }
  if (!s.time.empty()) ImGui::TextDisabled("t from %.3f to %.3f s", s.time.front(), s.time.back());
  ImGui::End();
}

void statusBar(const Snapshot& snap, double framesPerSecond, float y, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, y));
  ImGui::SetNextWindowSize(ImVec2(width, height));
  ImGui::Begin(
      "Status", nullptr,
      ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
  ImGui::TextUnformatted(statusLine(snap, framesPerSecond).c_str());
  // A failed run check in red after it, in full on hover (a long one runs past the window).
  const std::string failed = failedCheckStatus(snap);
  if (!failed.empty()) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.3f, 1.0f), "| %s", failed.c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", failed.c_str());
  }
  ImGui::End();
}

/// Colours per particle for the current colouring, and the colour bar's range [bottom, top].
std::vector<render::Rgba> colours(const Snapshot& snap, Colouring c, double& bottom, double& top) {
  std::vector<render::Rgba> out;
  bottom = top = 0;
  if (c == Colouring::None) return out;
  const std::vector<double>& v = c == Colouring::Force   ? snap.forceSum
                                 : c == Colouring::Speed ? snap.speed
                                                         : snap.stress33;
  for (double x : v) {
    top = std::max(top, x);
    bottom = std::min(bottom, x);
  }
  out.reserve(v.size());
  const double range = top - bottom;
  for (double x : v) out.push_back(render::viridis(range > 0 ? (x - bottom) / range : 0.0));
  return out;
}

void colourBar(Colouring c, double bottom, double top, float x, float y) {
  if (c == Colouring::None) return;
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const float width = 18, height = 200;
  for (int k = 0; k < 50; ++k) {
    const render::Rgba a = render::viridis(1.0 - k / 50.0);
    draw->AddRectFilled(ImVec2(x, y + k * height / 50),
                        ImVec2(x + width, y + (k + 1) * height / 50), IM_COL32(a.r, a.g, a.b, 255));
  }
  draw->AddRect(ImVec2(x, y), ImVec2(x + width, y + height), IM_COL32(40, 40, 40, 255));
  char label[64];
  const char* unit = c == Colouring::Force ? "N" : c == Colouring::Speed ? "m/s" : "Pa";
  std::snprintf(label, sizeof label, "%.3g %s", top, unit);
  draw->AddText(ImVec2(x + width + 4, y - 6), IM_COL32(20, 20, 20, 255), label);
  std::snprintf(label, sizeof label, "%.3g %s", bottom, unit);
  draw->AddText(ImVec2(x + width + 4, y + height - 8), IM_COL32(20, 20, 20, 255), label);
  draw->AddText(ImVec2(x, y + height + 6), IM_COL32(20, 20, 20, 255),
                c == Colouring::Force   ? "sum |F_ij|"
                : c == Colouring::Speed ? "speed"
                                        : "sigma33 (own volume)");
}

void writeScreenshot(const WindowGl& gl, int width, int height, const fs::path& file) {
  render::Image image(width, height);
  std::vector<std::uint8_t> rows(std::size_t(width) * height * 4);
  gl.pixelStorei(kPackAlignment, 1);
  gl.readPixels(0, 0, width, height, kRgba, kUnsignedByte, rows.data());
  for (int y = 0; y < height; ++y) {  // GL's rows run bottom-up
    std::memcpy(&image.pixels[std::size_t(y) * width * 4],
                &rows[std::size_t(height - 1 - y) * width * 4], std::size_t(width) * 4);
  }
  for (std::size_t k = 3; k < image.pixels.size(); k += 4) image.pixels[k] = 255;
  render::writePng(image, file, 96.0, 9);  // a screen at 96 dpi; small files for documents
}

/// Carries out the script one command per frame. Returns false when it asks to quit.
class ScriptPlayer {
 public:
  explicit ScriptPlayer(std::vector<ScriptCommand> commands) : commands_(std::move(commands)) {}

  bool advance(SimRunner& runner, UiState& ui, const Snapshot& snap) {
    if (waitFrames_ > 0) {
      --waitFrames_;
      return true;
    }
    if (waitSteps_) {
      if (runner.steps() < waitSteps_) {
        if (std::chrono::steady_clock::now() > deadline_) {
          throw std::runtime_error("script: wait-steps timed out after 600 s");
        }
        return true;
      }
      waitSteps_ = 0;
    }
    if (next_ >= commands_.size()) return true;
    const ScriptCommand& c = commands_[next_++];
    double x = 0;  // numeric arguments (parseScript checked them); others leave it 0
    try {
      x = std::stod(c.argument);
    } catch (const std::exception&) {
    }
    Material m = snap.material;
    const std::string& v = c.verb;
    if (v == "run") {
      runner.run();
    } else if (v == "pause") {
      runner.pause();
    } else if (v == "reset") {
      runner.reset();
    } else if (v == "stage2") {
      runner.startStage2();
    } else if (v == "step") {
      runner.step(int(x));
    } else if (v == "speed") {
      runner.setStepsPerUpdate(int(x));
    } else if (v == "wall-velocity") {
      runner.setTopWallVelocity(x);
    } else if (v == "frames") {
      waitFrames_ = long(x);
    } else if (v == "screenshot") {
      ui.screenshotRequest = c.argument;
    } else if (v == "save-view") {
      ui.viewRequest = c.argument;
    } else if (v == "load-checkpoint") {
      runner.loadCheckpoint(c.argument);
    } else if (v == "save-checkpoint") {
      runner.saveCheckpoint(c.argument);
    } else if (v == "export-figures") {
      std::snprintf(ui.figureFolder, sizeof ui.figureFolder, "%s", c.argument.c_str());
      startFigureExport(ui, snap);
      ui.figureExport.wait();  // a script goes on once they are written
    } else if (v == "quit") {
      return false;
    } else if (v == "colour") {
      ui.colouring = c.argument == "force"    ? Colouring::Force
                     : c.argument == "speed"  ? Colouring::Speed
                     : c.argument == "stress" ? Colouring::Stress
                                              : Colouring::None;
    } else if (v == "wait-steps") {
      waitSteps_ = runner.steps() + std::uint64_t(x);
      deadline_ = std::chrono::steady_clock::now() + std::chrono::seconds(600);
    } else {  // material fields
      if (c.verb == "mu") m.friction = x;
      if (c.verb == "gamma-n") m.normalDamping = x;
      if (c.verb == "gamma-t") m.tangentialDamping = x;
      if (c.verb == "youngs-modulus") m.youngModulus = x;
      if (c.verb == "material") {
        const MaterialSetting setting = materialSetting(c.argument);
        setting.parameter->set(m, setting.value);
      }
      runner.setMaterial(m);
    }
    runner.flush();  // the next frame shows the command's effect
    ui.synced = false;
    return true;
  }

 private:
  std::vector<ScriptCommand> commands_;
  std::size_t next_ = 0;
  long waitFrames_ = 0;
  std::uint64_t waitSteps_ = 0;
  std::chrono::steady_clock::time_point deadline_;
};

int runWindow(const GuiOptions& options) {
  ScriptPlayer script(parseScript(options.script));
  SimRunner runner(options.scene);  // a bad scene fails before any window opens

  glfwSetErrorCallback([](int code, const char* text) {
    std::fprintf(stderr, "granular-gui: GLFW error %d: %s\n", code, text);
  });
  if (!glfwInit()) {
    std::fprintf(stderr,
                 "granular-gui: cannot open a window (no display? DISPLAY=%s). The headless "
                 "figures need none: granular paper --out DIR\n",
                 std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "unset");
    return 2;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  GLFWwindow* window =
      glfwCreateWindow(options.width, options.height, "granular", nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "granular-gui: no OpenGL 3.3 core context on this display\n");
    glfwTerminate();
    return 2;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(options.frames > 0 || !options.script.empty() ? 0 : 1);
  int status = 0;
  {
    const WindowGl gl = loadWindowGl();
    render::ParticleRenderer renderer(reinterpret_cast<render::GlProcLoader>(glfwGetProcAddress));
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working folder
    addGreekGlyphs();
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");

    UiState ui;
    Snapshot snap;
    runner.latest(snap);
    std::uint64_t uploaded = 0;
    Colouring uploadedColouring = ui.colouring;
    double barBottom = 0, barTop = 0;
    // What the camera frames: the box and the walls as last uploaded.
    Vec3 viewMin = snap.boxMin, viewMax = snap.boxMax;
    long frame = 0;
    auto fpsStart = std::chrono::steady_clock::now();
    long fpsFrames = 0;
    double framesPerSecond = 0, meanFramesPerSecond = 0;
    const auto start = fpsStart;
    bool quit = false;
    while (!glfwWindowShouldClose(window) && !quit) {
      glfwPollEvents();
      if (!script.advance(runner, ui, snap)) quit = true;
      runner.latest(snap);
      int fbWidth = 0, fbHeight = 0, winWidth = 0, winHeight = 0;
      glfwGetFramebufferSize(window, &fbWidth, &fbHeight);
      glfwGetWindowSize(window, &winWidth, &winHeight);
      const float scale = winWidth > 0 ? float(fbWidth) / float(winWidth) : 1.0f;

      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      if (frame == 0) ui.labelsWithoutGlyphs = labelsWithoutGlyphs();
      const ControlsLayout layout = currentControlsLayout();
      const float panelWidth = layout.panelWidth, statusHeight = 30, plotsHeight = 250;
      const float viewX = panelWidth, viewW = float(winWidth) - panelWidth;
      const float viewH = float(winHeight) - statusHeight - plotsHeight;
      controlsPanel(runner, snap, ui, layout, float(winHeight) - statusHeight);
      plotsPanel(snap, viewX, viewH, viewW, plotsHeight);
      statusBar(snap, framesPerSecond, float(winHeight) - statusHeight, float(winWidth),
                statusHeight);

      // Mouse in the 3-D view: orbit, pan, zoom.
      ImGuiIO& io = ImGui::GetIO();
      const ImVec2 mouse = io.MousePos;
      const bool inView = mouse.x >= viewX && mouse.y >= 0 && mouse.y < viewH;
      if (inView && !io.WantCaptureMouse) {
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
          ui.orbit.orbit(io.MouseDelta.x, io.MouseDelta.y);
        }
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
          ui.orbit.pan(io.MouseDelta.x, io.MouseDelta.y, int(viewH));
        }
        if (io.MouseWheel != 0) ui.orbit.zoomBy(io.MouseWheel);
      }
      const Vec3 boxTop =
          snap.topWallZ ? Vec3(snap.boxMax.x(), snap.boxMax.y(), *snap.topWallZ) : snap.boxMax;
      if (snap.version != uploaded || ui.colouring != uploadedColouring ||
          !ui.viewRequest.empty()) {
        const std::vector<render::Rgba> c = colours(snap, ui.colouring, barBottom, barTop);
        render::ParticleScene scene;
        scene.centres = snap.centres;
        scene.radii = snap.radii;
        scene.colours = c;
        scene.lines = render::boxEdges(snap.boxMin, boxTop, !snap.topWallZ);
        // The walls where the run has them now: a stage may move them.
        const WallDrawing walls = wallDrawing(snap.walls);
        scene.surfaces = walls.triangles;
        scene.outlines = walls.outlines;
        std::tie(viewMin, viewMax) =
            render::boundsWith(snap.boxMin, boxTop, walls.triangles, walls.outlines);
        if (!ui.viewRequest.empty()) {  // offscreen, supersampled, as the figures are drawn
          const int w = std::max(2, int(2 * viewW)), h = std::max(2, int(2 * viewH));
          render::writePng(
              renderer.render(scene, ui.orbit.camera(viewMin, viewMax, double(w) / h), w, h),
              ui.viewRequest);
          ui.viewRequest.clear();
        }
        renderer.upload(scene);
        uploaded = snap.version;
        uploadedColouring = ui.colouring;
      }
      colourBar(ui.colouring, barBottom, barTop, viewX + viewW - 110, 30);
      ImGui::Render();

      // The 3-D view first, in its region; the panels over it.
      gl.viewport(0, 0, fbWidth, fbHeight);
      gl.clearColor(0.1f, 0.1f, 0.1f, 1.0f);
      gl.clear(kColorBufferBit | kDepthBufferBit);
      const int vx = int(viewX * scale), vy = int(plotsHeight * scale + statusHeight * scale);
      const int vw = std::max(1, int(viewW * scale)), vh = std::max(1, int(viewH * scale));
      gl.viewport(vx, vy, vw, vh);
      gl.scissor(vx, vy, vw, vh);
      gl.enable(kScissorTest);
      gl.clearColor(1.0f, 1.0f, 1.0f, 1.0f);
      gl.clear(kColorBufferBit | kDepthBufferBit);
      renderer.draw(ui.orbit.camera(viewMin, viewMax, double(vw) / vh), vw, vh, scale);
      gl.disable(kScissorTest);
      gl.viewport(0, 0, fbWidth, fbHeight);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

      ++frame;
      if (options.frames > 0 && frame >= options.frames) quit = true;
      if (!ui.screenshotRequest.empty()) {
        writeScreenshot(gl, fbWidth, fbHeight, ui.screenshotRequest);
        ui.screenshotRequest.clear();
      }
      if (quit && !options.screenshot.empty()) {
        writeScreenshot(gl, fbWidth, fbHeight, options.screenshot);
      }
      glfwSwapBuffers(window);
      ++fpsFrames;
      const auto now = std::chrono::steady_clock::now();
      const double elapsed = std::chrono::duration<double>(now - fpsStart).count();
      if (elapsed >= 0.5) {
        framesPerSecond = fpsFrames / elapsed;
        fpsStart = now;
        fpsFrames = 0;
      }
      meanFramesPerSecond =
          frame / std::max(1e-9, std::chrono::duration<double>(now - start).count());
    }
    runner.pause();
    runner.flush();
    runner.latest(snap);
    std::printf(
        "granular-gui: %ld frames, %.1f frames/s; stage %d, t = %.6f s, %llu steps, mu = %g, "
        "%zu contacts%s%s\n",
        frame, meanFramesPerSecond, snap.stage, snap.time,
        static_cast<unsigned long long>(snap.steps), snap.material.friction, snap.particleContacts,
        snap.message.empty() ? "" : "; last message: ", snap.message.c_str());
    // Labels that do not show whole: said, for the window's test.
    auto list = [](const std::set<std::string>& labels) {
      std::string text;
      for (const std::string& l : labels) text += (text.empty() ? "" : ", ") + l;
      return text;
    };
    if (!ui.cutOffLabels.empty()) {
      int width = 0, height = 0;
      glfwGetWindowSize(window, &width, &height);
      std::fprintf(stderr, "granular-gui: labels cut off in a window of %d x %d: %s\n", width,
                   height, list(ui.cutOffLabels).c_str());
    }
    if (!ui.labelsWithoutGlyphs.empty()) {
      std::fprintf(stderr,
                   "granular-gui: labels with characters the font lacks (drawn as '?'): %s\n",
                   list(ui.labelsWithoutGlyphs).c_str());
    }
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }  // the renderer's GL objects go before the context
  glfwDestroyWindow(window);
  glfwTerminate();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    GuiOptions options;
    options.scene = fs::path(GRANULAR_SCENES_DIR) / "paper-mu03.toml";
    if (!parseGuiOptions(argc, argv, options, std::cout)) return 0;
    return runWindow(options);
  } catch (const std::invalid_argument& e) {  // a bad option or script: 2, as for granular
    std::fprintf(stderr, "granular-gui: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "granular-gui: %s\n", e.what());
    return 1;
  }
}
