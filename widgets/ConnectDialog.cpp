#include "widgets/ConnectDialog.h"

#include <QButtonGroup>
#include <QComboBox>
#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QRadioButton>
#include <QSpinBox>
#include <QVBoxLayout>

namespace ambler::widgets {

namespace {

// A line edit with a Browse button that fills it.
QWidget* withBrowse(QLineEdit* edit, QWidget* parent, const QString& title, const QString& filter) {
  auto* row = new QWidget;
  auto* layout = new QHBoxLayout(row);
  layout->setContentsMargins(0, 0, 0, 0);
  auto* browse = new QPushButton(QObject::tr("Browse…"));
  layout->addWidget(edit, 1);
  layout->addWidget(browse);
  QObject::connect(browse, &QPushButton::clicked, parent, [=] {
    const QString path = QFileDialog::getOpenFileName(parent, title, edit->text(), filter);
    if (!path.isEmpty()) edit->setText(path);
  });
  return row;
}

}  // namespace

ConnectDialog::ConnectDialog(const ConnectChoice& initial, QWidget* parent)
    : QDialog(parent),
      sources_(new QButtonGroup(this)),
      seed_(new QSpinBox),
      family_(new QComboBox),
      domain_(new QSpinBox),
      rover_id_(new QSpinBox),
      key_file_(new QLineEdit),
      log_file_(new QLineEdit),
      problem_(new QLabel),
      buttons_(new QDialogButtonBox(QDialogButtonBox::Ok | QDialogButtonBox::Cancel)) {
  setWindowTitle(tr("Connect"));
  seed_->setRange(1, 999999);
  for (const auto f : sim::kTerrainFamilies) {
    QString title =
        QString::fromUtf8(sim::familyTitle(f).data(), qsizetype(sim::familyTitle(f).size()));
    title[0] = title[0].toUpper();
    family_->addItem(f == sim::TerrainFamily::kCourse ? tr("Obstacle course") : title, int(f));
  }
  domain_->setRange(0, 232);  // DDS domain ids over UDP
  rover_id_->setRange(1, 65535);
  key_file_->setPlaceholderText(tr("operator key file (name and 64 hex digits)"));
  log_file_->setPlaceholderText(tr("mission log (.sqlite)"));
  problem_->setStyleSheet("color:#b71c1c");
  problem_->setWordWrap(true);

  auto* layout = new QVBoxLayout(this);
  auto addSource = [&](ConnectChoice::Source id, const QString& text, QLayout* fields) {
    auto* radio = new QRadioButton(text);
    sources_->addButton(radio, int(id));
    layout->addWidget(radio);
    auto* box = new QWidget;
    box->setLayout(fields);
    box->setContentsMargins(24, 0, 0, 0);
    layout->addWidget(box);
    connect(radio, &QRadioButton::toggled, box, &QWidget::setEnabled);
    box->setEnabled(false);
  };
  auto* sim = new QFormLayout;
  sim->addRow(tr("Ground"), family_);
  sim->addRow(tr("Ground seed"), seed_);
  addSource(ConnectChoice::Source::kSimulator, tr("Built-in simulator (in this process)"), sim);
  auto* dds = new QFormLayout;
  dds->addRow(tr("DDS domain"), domain_);
  dds->addRow(tr("Rover id"), rover_id_);
  dds->addRow(tr("Operator key"),
              withBrowse(key_file_, this, tr("Operator key"), tr("Keys (*.key);;All files (*)")));
  addSource(ConnectChoice::Source::kDds, tr("ambler-sim or a rover over DDS"), dds);
  auto* log = new QFormLayout;
  log->addRow(tr("Log file"), withBrowse(log_file_, this, tr("Mission log"),
                                         tr("Mission logs (*.sqlite);;All files (*)")));
  addSource(ConnectChoice::Source::kLog, tr("Replay a mission log"), log);
  layout->addWidget(problem_);
  layout->addWidget(buttons_);
  connect(buttons_, &QDialogButtonBox::accepted, this, &QDialog::accept);
  connect(buttons_, &QDialogButtonBox::rejected, this, &QDialog::reject);
  connect(sources_, &QButtonGroup::idToggled, this, &ConnectDialog::check);
  connect(key_file_, &QLineEdit::textChanged, this, &ConnectDialog::check);
  connect(log_file_, &QLineEdit::textChanged, this, &ConnectDialog::check);
  setChoice(initial);
}

ConnectChoice ConnectDialog::choice() const {
  ConnectChoice c;
  c.source = ConnectChoice::Source(sources_->checkedId());
  c.seed = quint64(seed_->value());
  c.family = sim::TerrainFamily(family_->currentData().toInt());
  c.on_terrain_model = on_terrain_model_;
  c.domain = domain_->value();
  c.rover_id = quint32(rover_id_->value());
  c.key_file = key_file_->text().trimmed();
  c.log_file = log_file_->text().trimmed();
  return c;
}

void ConnectDialog::setChoice(const ConnectChoice& c) {
  sources_->button(int(c.source))->setChecked(true);
  seed_->setValue(int(c.seed));
  family_->setCurrentIndex(family_->findData(int(c.family)));
  on_terrain_model_ = c.on_terrain_model;
  family_->setEnabled(!c.on_terrain_model);
  family_->setToolTip(c.on_terrain_model ? tr("Launched on a terrain model (--dtm)") : QString());
  domain_->setValue(c.domain);
  rover_id_->setValue(int(c.rover_id));
  key_file_->setText(c.key_file);
  log_file_->setText(c.log_file);
  check();
}

Refusal ConnectDialog::problem() const {
  const auto c = choice();
  auto readable = [](const QString& path, const QString& what) -> Refusal {
    if (path.isEmpty()) return Refusal::because(tr("Choose %1.").arg(what).toStdString());
    const QFileInfo info(path);
    if (!info.isFile() || !info.isReadable())
      return Refusal::because(tr("%1 is not a readable file.").arg(path).toStdString());
    return {};
  };
  switch (c.source) {
    case ConnectChoice::Source::kDds:
      return readable(c.key_file, tr("the operator key file"));
    case ConnectChoice::Source::kLog:
      return readable(c.log_file, tr("a mission log"));
    case ConnectChoice::Source::kSimulator:
      return {};
  }
  return {};
}

void ConnectDialog::check() {
  const auto usable = problem();
  problem_->setText(QString::fromStdString(usable.why()));
  buttons_->button(QDialogButtonBox::Ok)->setEnabled(!usable.refused());
}

}  // namespace ambler::widgets
