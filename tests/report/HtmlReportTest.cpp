// The report is tested in a real browser: headless Chromium loads report.html from disk (no
// network), the page must finish its script without errors (title), the 3-D canvas must have
// drawn pixels, the plots must be there, and a screenshot is saved into the build folder.
#include <cstdlib>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/report/HtmlReport.h"

namespace tkgslam {
namespace {

std::string chromium() {
  for (const char* c : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"}) {
    if (std::filesystem::exists(c)) return c;
  }
  return "";
}

std::string runCapture(const std::string& cmd) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return out;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  pclose(p);
  return out;
}

TEST(HtmlReport, RendersInHeadlessChromium) {
  TKGSLAM_REQUIRE_SHARED();
  const std::string browser = chromium();
  if (browser.empty()) GTEST_SKIP() << "Chromium is not installed (apt-get install chromium); skipped";
  test::TempDir tmp;
  const auto out = tmp / "run";
  std::string log;
  // A short TKG run on the real sequence (a seated person is detected), with the report.
  ASSERT_EQ(test::runCli("run --deterministic -q --report --mode TKG --max-frames 60 -c " +
                             (test::sourceDir() / "configs/tum_fr1.yaml").string() + " -d " + test::fr1xyz().string() +
                             " -o " + out.string(),
                         &log),
            0)
      << log;
  ASSERT_TRUE(std::filesystem::exists(out / "report.html")) << log;
  const std::string flags =
      " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking "
      "--disable-component-update --disable-sync --user-data-dir=" + (tmp / "profile").string();
  const std::string url = "file://" + (out / "report.html").string();
  const std::string dom = runCapture(browser + flags + " --dump-dom " + url + " 2>/dev/null");
  EXPECT_NE(dom.find("<title>tkgslam report ready</title>"), std::string::npos)
      << "script error or not finished: " << dom.substr(0, 300);
  const auto at = dom.find("data-drawn-pixels=\"");
  ASSERT_NE(at, std::string::npos) << "3-D canvas not drawn";
  EXPECT_GT(std::stol(dom.substr(at + 19)), 500) << "3-D canvas is blank";
  EXPECT_NE(dom.find("data-renderer=\"webgl\""), std::string::npos) << "the 3-D view did not use WebGL";
  int plots = 0;
  for (size_t p = dom.find("<svg class=\"plot\""); p != std::string::npos; p = dom.find("<svg class=\"plot\"", p + 1)) ++plots;
  EXPECT_GE(plots, 5);  // error, RPE, timing, T, boxes, dropped
  EXPECT_NE(dom.find("data:image/jpeg;base64,"), std::string::npos) << "no thumbnails";
  for (const char* remote : {"src=\"http", "href=\"http", "url(http"}) {
    EXPECT_EQ(dom.find(remote), std::string::npos) << "the page must not load anything from the network";
  }

  // Screenshot into the build folder, for people to look at; it must not be blank.
  const auto shot = std::filesystem::current_path() / "report_screenshot.png";
  runCapture(browser + flags + "2 --window-size=1200,2600 --screenshot=" + shot.string() + " " + url + " 2>/dev/null");
  const cv::Mat img = cv::imread(shot.string());
  ASSERT_FALSE(img.empty()) << "no screenshot at " << shot;
  cv::Scalar mean, stddev;
  cv::meanStdDev(img, mean, stddev);
  EXPECT_GT(stddev[0], 10.0) << "screenshot is blank";
}

TEST(HtmlReport, NotARunFolderIsAClearError) {
  test::TempDir tmp;
  EXPECT_THROW(report::writeHtmlReport(tmp.path().string()), InputError);
  std::string out;
  EXPECT_EQ(test::runCli("report " + tmp.path().string(), &out), 2);
  EXPECT_NE(out.find("not the output folder"), std::string::npos) << out;
}

/// A run folder without ground truth or images: run.json, a two-pose trajectory and dynamic.jsonl.
void writeSmallRun(const std::filesystem::path& dir, const std::string& dynamic_jsonl) {
  test::writeText(dir / "run.json", "{\"dataset\": \"\", \"mode\": \"TKG\", \"frames\": 2, \"ratio_threshold\": 0.7}\n");
  test::writeText(dir / "trajectory.txt", "1.0 0 0 0 0 0 0 1\n1.1 0.01 0 0 0 0 0 1\n");
  test::writeText(dir / "dynamic.jsonl", dynamic_jsonl);
}

const char* const kDynamicLine =
    "{\"timestamp\": 1.0, \"T\": 0.4, \"dropped\": 12, \"boxes\": [{\"x\": 10.0, \"y\": 20.0, \"w\": 30.0, "
    "\"h\": 40.0, \"class\": 0, \"score\": 0.9, \"predicted\": false, \"track\": 0}]}\n";

TEST(HtmlReport, SmallRunFolderWithoutGroundTruth) {
  test::TempDir tmp;
  writeSmallRun(tmp.path(), std::string(kDynamicLine) + kDynamicLine);
  const std::string html = test::readFile(report::writeHtmlReport(tmp.path().string()));
  EXPECT_NE(html.find("No ground truth: accuracy plots omitted."), std::string::npos);
  EXPECT_NE(html.find("<h2>Dynamic objects</h2>"), std::string::npos);
  EXPECT_NE(html.find("<tr><th>frames</th><td>2</td></tr>"), std::string::npos);
}

TEST(HtmlReport, DatasetPathWithQuoteAndBackslashIsReadBack) {
  // run.json escapes them (\" and \\); the report used to cut the path at the quote, and so lost
  // the ground truth's accuracy section without a word.
  test::TempDir tmp;
  const std::filesystem::path dataset = tmp.path() / "we\"ird\\seq";
  std::filesystem::create_directories(dataset);
  test::writeText(dataset / "groundtruth.txt", "1.0 0 0 0 0 0 0 1\n1.1 0.01 0 0 0 0 0 1\n");
  const std::filesystem::path run = tmp.path() / "run";
  writeSmallRun(run, kDynamicLine);
  std::string escaped;
  for (const char c : dataset.string()) escaped += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  test::writeText(run / "run.json", "{\"dataset\": \"" + escaped + "\", \"mode\": \"TKG\", \"frames\": 2}\n");
  const std::string html = test::readFile(report::writeHtmlReport(run.string()));
  EXPECT_NE(html.find("we&quot;ird\\seq</code>"), std::string::npos);
  EXPECT_NE(html.find("ATE RMSE 0.0000 m over 2 poses"), std::string::npos);
  EXPECT_EQ(html.find("No ground truth"), std::string::npos);
}

TEST(HtmlReport, RunJsonThatIsNotJsonIsAClearError) {
  test::TempDir tmp;
  writeSmallRun(tmp.path(), kDynamicLine);
  test::writeText(tmp.path() / "run.json", "{\"dataset\": \"/tmp/x, \"mode\": \n");  // cut short
  std::string out;
  EXPECT_EQ(test::runCli("report " + tmp.path().string(), &out), 2);
  EXPECT_NE(out.find("run.json: not valid JSON"), std::string::npos) << out;
}

TEST(HtmlReport, MalformedDynamicLogNamesTheLine) {
  test::TempDir tmp;
  // Line 2 has no number for T; line 2 of the second file a box whose x is not a number.
  writeSmallRun(tmp.path(), std::string(kDynamicLine) + "{\"timestamp\": 1.1, \"T\": x, \"dropped\": 0}\n");
  std::string out;
  EXPECT_EQ(test::runCli("report " + tmp.path().string(), &out), 2);
  EXPECT_NE(out.find("dynamic.jsonl:2: no number \"T\""), std::string::npos) << out;

  std::string bad_box = kDynamicLine;
  bad_box.replace(bad_box.find("10.0"), 4, "-");
  writeSmallRun(tmp.path(), std::string(kDynamicLine) + bad_box);
  EXPECT_EQ(test::runCli("report " + tmp.path().string(), &out), 2);
  EXPECT_NE(out.find("dynamic.jsonl:2: bad box"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
