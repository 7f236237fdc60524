// The viewer as a mapper drives it: taps shorter than a frame, screenshots that fail, a map that
// is broken when the window opens, a texture that appears. Keys reach the window as X events
// (XSendEvent to the viewer's window), so they go through GLFW's event processing and the
// viewer's callbacks exactly as a user's key presses do; nothing is injected behind GLFW.
#include "tests/viewer/viewer_test_fixture.h"
#include "tests/viewer/x_keys.h"

#include <GLFW/glfw3.h>
#include <X11/Xlib.h>
#include <X11/keysym.h>

#include <algorithm>
#include <iterator>
#include <thread>

namespace bt {
namespace {

using namespace viewer_test;

// The pointer moved to (x, y) of the window and a left click there.
void click(const Viewer& viewer, int x, int y) {
  Display* display = XOpenDisplay(nullptr);
  ASSERT_NE(display, nullptr);
  const Window window = viewer.x11Window();
  XWarpPointer(display, None, window, 0, 0, 0, 0, x, y);
  XButtonEvent event{};
  event.display = display;
  event.window = window;
  event.root = DefaultRootWindow(display);
  event.time = CurrentTime;
  event.x = x;
  event.y = y;
  event.same_screen = True;
  event.button = Button1;
  event.type = ButtonPress;
  XSendEvent(display, window, True, ButtonPressMask, reinterpret_cast<XEvent*>(&event));
  event.type = ButtonRelease;
  event.state = Button1Mask;
  XSendEvent(display, window, True, ButtonReleaseMask, reinterpret_cast<XEvent*>(&event));
  XSync(display, False);
  XCloseDisplay(display);
}

std::string allMessages(const Viewer& viewer) {
  std::string text;
  for (const OverlayMessage& m : viewer.messages()) text += m.text + "\n";
  return text;
}

bool hasMessage(const Viewer& viewer, OverlayMessage::Kind kind, const std::string& part) {
  const auto messages = viewer.messages();
  return std::any_of(messages.begin(), messages.end(),
                     [&](const OverlayMessage& m) { return m.kind == kind && m.text.find(part) != std::string::npos; });
}

TEST_F(ViewerWindowTest, ATapShorterThanAFrameIsActedOn) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));

  tap(viewer, XK_F12);
  tap(viewer, XK_2);
  tap(viewer, XK_5);
  ASSERT_TRUE(viewer.frame());
  const fs::path shot = dir_ / "room-000.png";
  EXPECT_TRUE(fs::exists(shot)) << "the F12 tap was lost";
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Info, shot.string())) << allMessages(viewer);
  EXPECT_EQ(viewer.mode(), ViewMode::Fullbright) << "the 2 tap was lost";
  EXPECT_EQ(viewer.lighting(), LightingMode::Physical) << "the 5 tap was lost";

  // F1 hides the overlay and shows it again, one tap each, in the same frame too.
  tap(viewer, XK_F1);
  ASSERT_TRUE(viewer.frame());
  EXPECT_FALSE(viewer.overlayShown());
  tap(viewer, XK_F1);
  tap(viewer, XK_F1);
  tap(viewer, XK_F1);
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(viewer.overlayShown()) << "three taps in one frame did not toggle three times";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// L: the room's light as a gizmo of its reach. Seen from 100 units in front of it, its rings
// (reach 300 / 4 = 75 units apart, facing the camera) land 36 pixels from the centre of this
// 96x64 window (90 degree field of view); the image elsewhere is left as it was.
TEST_F(ViewerWindowTest, LShowsTheLightsReachAroundIt) {
  ViewerOptions o = options();
  o.camera = CameraPose{glm::vec3(-100, 0, 64), 0, 0, 0, "test"};
  o.maxSamples = 1; // the image stays as it is between the two reads, markers aside
  o.luxels = false;
  Viewer viewer(o);
  tap(viewer, XK_F1);
  ASSERT_TRUE(viewer.frame());
  const Viewer::DisplayImage before = viewer.window();
  tap(viewer, XK_l);
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(viewer.markersShown());
  const Viewer::DisplayImage after = viewer.window();
  ASSERT_EQ(after.width, 96);
  ASSERT_EQ(after.height, 64);
  const auto at = [](const Viewer::DisplayImage& image, int x, int y) { return &image.rgba[(size_t(y) * image.width + x) * 4]; };
  const auto changedNear = [&](float x, float y) {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int px = int(x) + dx, py = int(y) + dy;
        if (!std::equal(at(before, px, py), at(before, px, py) + 3, at(after, px, py))) return true;
      }
    return false;
  };
  int onRing = 0, inWindow = 0;
  for (int k = 0; k < 32; ++k) {
    const float a = 2.0f * 3.14159265f * float(k) / 32.0f, x = 48.0f + 36.0f * std::cos(a), y = 32.0f + 36.0f * std::sin(a);
    if (y < 1.5f || y > 62.5f) continue; // the ring leaves this short window at the top and bottom
    ++inWindow;
    onRing += changedNear(x, y);
  }
  EXPECT_GE(inWindow, 12);
  EXPECT_EQ(onRing, inWindow) << "the first ring (75 units) is not 36 pixels from the light everywhere";
  const uint8_t* centre = at(after, 48, 32);
  EXPECT_GE(std::min({centre[0], centre[1], centre[2]}), 250) << "the light's dot is not white";
  EXPECT_TRUE(std::equal(at(before, 10, 5), at(before, 10, 5) + 3, at(after, 10, 5))) << "a pixel between the rings changed";
  tap(viewer, XK_l);
  ASSERT_TRUE(viewer.frame());
  EXPECT_FALSE(viewer.markersShown());
}

// Ctrl+digit keeps the camera in the user's bookmarks file; Alt+digit in a later session of the
// same level goes back to it.
TEST_F(ViewerWindowTest, BookmarksOutliveTheSession) {
  ViewerOptions o = options();
  o.bookmarksFile = dir_ / "config" / "bookmarks.json";
  o.camera = CameraPose{glm::vec3(-50, 20, -30), 10, 45, 0, "test"};
  {
    Viewer viewer(o);
    ASSERT_TRUE(viewer.frame());
    tap(viewer, XK_3, ControlMask);
    ASSERT_TRUE(viewer.frame());
    EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Info, "bookmark 3: (-50 20 -30) 10 45 0")) << allMessages(viewer);
  }
  ASSERT_TRUE(fs::exists(o.bookmarksFile));
  o.camera = CameraPose{glm::vec3(0, 0, 0), 0, 0, 0, "test"};
  Viewer viewer(o);
  ASSERT_TRUE(viewer.frame());
  tap(viewer, XK_4, Mod1Mask);
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Warning, "no bookmark 4")) << allMessages(viewer);
  EXPECT_EQ(viewer.camera().origin, glm::vec3(0, 0, 0));
  tap(viewer, XK_3, Mod1Mask);
  ASSERT_TRUE(viewer.frame());
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-50, 20, -30));
  EXPECT_NEAR(viewer.camera().pitch, 10.0f, 1e-4f);
  EXPECT_NEAR(viewer.camera().yaw, 45.0f, 1e-4f);
  EXPECT_EQ(viewer.lighting(), LightingMode::Faithful) << "Alt+4 was taken as key 4";
}

// A bookmarks file that cannot be written (its folder is a file) or is not ours to rewrite:
// the overlay says so, the file is left as it is, and the bookmark is still there this session.
TEST_F(ViewerWindowTest, ABookmarkThatCannotBeSavedIsKeptForTheSession) {
  ViewerOptions o = options();
  std::ofstream(dir_ / "damaged.json") << "{ not json";
  for (const fs::path& file : {dir_ / "damaged.json", dir_ / "room.map" / "bookmarks.json"}) {
    o.bookmarksFile = file;
    o.camera = CameraPose{glm::vec3(-60, 10, -20), 0, 30, 0, "test"};
    Viewer viewer(o);
    ASSERT_TRUE(viewer.frame());
    tap(viewer, XK_1, ControlMask);
    ASSERT_TRUE(viewer.frame());
    EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Error, "bookmark kept for this session only: " + file.string()))
        << allMessages(viewer);
    tap(viewer, XK_1, Mod1Mask);
    ASSERT_TRUE(viewer.frame());
    EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Info, "bookmark 1: (-60 10 -20) 0 30 0")) << allMessages(viewer);
  }
  std::ifstream in(dir_ / "damaged.json");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "{ not json") << "the damaged file was rewritten";
}

// Ctrl+C: a press with its modifier, through the same queue.
TEST_F(ViewerWindowTest, CtrlCCopiesTheCameraForRenderAndForTheGame) {
  Viewer viewer(options());
  ASSERT_TRUE(viewer.frame());
  tap(viewer, XK_c, ControlMask);
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Info, "copied the camera: (-96 0 -42) 0 0 0")) << allMessages(viewer);
  const char* text = glfwGetClipboardString(nullptr); // the viewer's window owns the selection
  ASSERT_NE(text, nullptr);
  EXPECT_EQ(std::string(text), "--camera '(-96 0 -42) 0 0 0'\nsetpos -96 0 -42 0 0 0\n");
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-96, 0, -42)) << "the C of Ctrl+C moved the camera";
}

// The room's +X wall is brush 1 (line 14 of the map), its -X face on line 15: straight ahead of
// the camera, under the window's centre.
TEST_F(ViewerWindowTest, AClickShowsTheFaceUnderTheCursorWithItsFileLineAndLights) {
  Viewer viewer(options());
  tap(viewer, XK_F1); // the overlay covers most of this small window, and a click on it is its own
  ASSERT_TRUE(viewer.frame());
  click(viewer, 48, 32);
  ASSERT_TRUE(viewer.frame());
  const PickedFace& picked = viewer.picked();
  ASSERT_TRUE(picked.hit) << "the click picked nothing";
  EXPECT_EQ(picked.fileLine, map_.string() + ":15");
  std::string lines;
  for (const std::string& line : picked.lines) lines += line + "\n";
  EXPECT_NE(lines.find("brush 1: " + map_.string() + ":14"), std::string::npos) << lines;
  EXPECT_NE(lines.find("texture wall"), std::string::npos) << lines;
  EXPECT_NE(lines.find("entity 0 worldspawn: " + map_.string() + ":3"), std::string::npos) << lines;
  EXPECT_NE(lines.find("solid"), std::string::npos) << lines;
  // The room's one light (its entity on line 55) gives the wall all of its light.
  EXPECT_NE(lines.find("100.0 %  light (0 0 64) " + map_.string() + ":55"), std::string::npos) << lines;

  tap(viewer, XK_c, ControlMask | ShiftMask);
  ASSERT_TRUE(viewer.frame());
  const char* text = glfwGetClipboardString(nullptr);
  ASSERT_NE(text, nullptr);
  EXPECT_EQ(std::string(text), map_.string() + ":15");
}

// Physical mode (key 5, once the level is up): the same click breaks the light down by light too, the room's one light
// first and the bounced light after, and the percentages add up to the light shown.
TEST_F(ViewerWindowTest, AClickInPhysicalModeShowsThePhysicalLightsShares) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; })); // the level is up
  tap(viewer, XK_F1);
  tap(viewer, XK_5);
  ASSERT_TRUE(viewer.frame());
  ASSERT_EQ(viewer.lighting(), LightingMode::Physical);
  click(viewer, 48, 32);
  ASSERT_TRUE(viewer.frame());
  const PickedFace& picked = viewer.picked();
  ASSERT_TRUE(picked.hit) << "the click picked nothing";
  std::string lines;
  double percents = 0.0;
  int shareLines = 0;
  for (const std::string& line : picked.lines) {
    lines += line + "\n";
    if (const size_t at = line.find(" %  "); at != std::string::npos) percents += std::stod(line.substr(0, at)), ++shareLines;
  }
  EXPECT_NE(lines.find("physical light here"), std::string::npos) << lines;
  const size_t light = lines.find(" %  light (0 0 64) " + map_.string() + ":55"), rest = lines.find(" %  sky, emitting surfaces");
  EXPECT_NE(light, std::string::npos) << lines;
  EXPECT_NE(rest, std::string::npos) << lines;
  EXPECT_LT(light, rest) << "the light is not named first";
  EXPECT_NEAR(percents, 100.0, 0.05 * double(shareLines) + 1e-6) << lines; // each line rounded to 0.1 %
}

TEST_F(ViewerWindowTest, AScreenshotIntoAFolderThatIsGoneShowsTheErrorAndTheViewerGoesOn) {
  ViewerOptions o = options();
  o.screenshotDir = dir_ / "shots";
  fs::create_directories(o.screenshotDir);
  Viewer viewer(o);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
  fs::remove(o.screenshotDir); // removed while the viewer runs

  tap(viewer, XK_F12);
  ASSERT_TRUE(viewer.frame()) << "the failed screenshot closed the viewer";
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Error, "screenshot failed")) << allMessages(viewer);
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Error, (o.screenshotDir / "room-000.png").string())) << allMessages(viewer);
  const int samples = viewer.samples();
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() > samples; })) << "refinement stopped";

  // The folder is back: the next F12 writes there and says where.
  fs::create_directories(o.screenshotDir);
  tap(viewer, XK_F12);
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(fs::exists(o.screenshotDir / "room-000.png"));
  EXPECT_TRUE(fs::exists(o.screenshotDir / "room-000.exr"));
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Info, (o.screenshotDir / "room-000.png").string())) << allMessages(viewer);
  EXPECT_FALSE(hasMessage(viewer, OverlayMessage::Kind::Error, "screenshot failed")) << allMessages(viewer);
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

TEST_F(ViewerWindowTest, AMapBrokenAtStartUpShowsTheErrorUntilASaveFixesIt) {
  std::ofstream(map_) << "{\n\"classname\" \"worldspawn\"\n{\n( 0 0 0 ) ( 1 0";
  Viewer viewer(options());
  EXPECT_FALSE(viewer.hasLevel());
  EXPECT_NE(viewer.error().find(map_.string() + ":4:"), std::string::npos) << "no file:line:col: " << viewer.error();
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Error, map_.string() + ":4:")) << allMessages(viewer);
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(viewer.frame()) << "the window without a level closed";
  tap(viewer, XK_F12); // nothing to shoot: said so, and the viewer goes on
  ASSERT_TRUE(viewer.frame());
  EXPECT_TRUE(hasMessage(viewer, OverlayMessage::Kind::Error, "screenshot failed")) << allMessages(viewer);

  save(roomMap(300));
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.hasLevel() && viewer.samples() >= 2; })) << "the fixed save was not loaded";
  EXPECT_TRUE(viewer.error().empty()) << viewer.error();
  EXPECT_EQ(viewer.camera().origin, glm::vec3(-96, 0, -42)) << "the level did not open at its render camera";
  const fs::path shot = viewer.screenshot();
  EXPECT_GT(meanPixel(shot), 5.0) << "the fixed level rendered black";
  EXPECT_LE(largestDifference(shot, viewer.displayed()), 1) << "the window does not show the level";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

TEST_F(ViewerWindowTest, ATextureThatAppearsReloadsTheLevel) {
  fs::remove(dir_ / "textures/wall.png");
  fs::remove(dir_ / "textures/wall_norm.png");
  Viewer viewer(options());
  const auto warnings = viewer.warnings();
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not found"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("wall"), std::string::npos) << warnings[0];
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 2; }));
  const fs::path checker = viewer.screenshot();

  writeTexture(dir_ / "textures/wall.png", 250);
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.reloads() == 1 && viewer.samples() >= 2; }))
      << "the texture that appeared did not reload the level";
  EXPECT_TRUE(viewer.warnings().empty()) << viewer.warnings().front();
  const fs::path textured = viewer.screenshot();
  EXPECT_GT(meanPixel(textured), meanPixel(checker) * 1.2) << "the level still shows the checker";
  EXPECT_EQ(viewer.glDebugErrors(), 0);
}

// The save is noticed by the watcher's thread while a frame is busy, and the reload's import runs
// on a worker thread: the frames go on meanwhile and the level changes between two of them.
TEST_F(ViewerWindowTest, ASaveIsNoticedWhileAFrameIsBusy) {
  Viewer viewer(options());
  ASSERT_TRUE(frameUntil(viewer, [&] { return viewer.samples() >= 1; }));
  save(roomMap(900));
  std::this_thread::sleep_for(std::chrono::milliseconds(600)); // a frame that takes 0.6 s
  ASSERT_TRUE(viewer.frame());
  // Polled by the frame, the save would only now be seen, and waited for another debounce.
  EXPECT_TRUE(viewer.reloading() || viewer.reloads() == 1) << "the first frame after the save did not start the reload";
  ASSERT_TRUE(frameUntil(
      viewer, [&] { return viewer.reloads() == 1; }, 10.0))
      << "the save was not noticed";
}

} // namespace
} // namespace bt
