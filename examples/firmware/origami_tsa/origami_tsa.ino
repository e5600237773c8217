// Reference firmware of the origami_cad generic serial protocol (docs/serial-protocol.md).
// Board: Arduino Uno/Nano or ESP32. Motors: continuous-rotation servos with an encoder, or
// steppers; here STEP/DIR stepper drivers (e.g. A4988) are assumed, 200 steps x 16 microsteps.
// Commands: P <id> | G <id> <turns> | R <id> | S, each line ending in *HH (CRC-8/SMBUS).

#include <Arduino.h>

const int N_MOTORS = 4;
const int STEP_PIN[N_MOTORS] = {2, 4, 6, 8};
const int DIR_PIN[N_MOTORS] = {3, 5, 7, 9};
const int ENABLE_PIN = 10;            // active low, shared
const long STEPS_PER_TURN = 3200;     // 200 full steps x 16 microsteps
const unsigned long STEP_INTERVAL_US = 150;  // speed limit
const long MODEL = 9000;

long position[N_MOTORS];   // steps
long goal[N_MOTORS];       // steps
bool enabled = false;
unsigned long lastStep = 0;
char line[64];
int lineLen = 0;

uint8_t crc8(const char *data, int len) {
  uint8_t crc = 0;
  for (int i = 0; i < len; i++) {
    crc ^= (uint8_t)data[i];
    for (int b = 0; b < 8; b++) crc = (crc & 0x80) ? (uint8_t)((crc << 1) ^ 0x07) : (uint8_t)(crc << 1);
  }
  return crc;
}

void reply(const char *text) {
  char out[80];
  snprintf(out, sizeof(out), "%s*%02X", text, crc8(text, strlen(text)));
  Serial.println(out);
}

void handle(char *text) {
  char *star = strrchr(text, '*');
  if (!star || strlen(star) != 3 || strtol(star + 1, NULL, 16) != crc8(text, star - text)) {
    reply("ERR 1 checksum");
    return;
  }
  *star = '\0';
  char cmd = text[0];
  int id = -1;
  char buf[64];
  if (cmd == 'S' && text[1] == '\0') {
    enabled = false;
    digitalWrite(ENABLE_PIN, HIGH);
    for (int i = 0; i < N_MOTORS; i++) goal[i] = position[i];
    reply("OK S");
    return;
  }
  if (cmd != 'P' && cmd != 'G' && cmd != 'R') { reply("ERR 2 unknown command"); return; }
  if (sscanf(text + 1, "%d", &id) != 1) { reply("ERR 5 syntax"); return; }
  if (id < 1 || id > N_MOTORS) { reply("ERR 3 unknown id"); return; }
  int m = id - 1;
  if (cmd == 'P') {
    snprintf(buf, sizeof(buf), "OK P %d %ld", id, MODEL);
    reply(buf);
  } else if (cmd == 'R') {
    char turns[16];
    dtostrf((double)position[m] / STEPS_PER_TURN, 1, 4, turns);
    snprintf(buf, sizeof(buf), "OK R %d %s %d", id, turns, enabled ? 60 : 0);
    reply(buf);
  } else {
    char *arg = strchr(text + 2, ' ');
    if (!arg) { reply("ERR 5 syntax"); return; }
    double turns = atof(arg + 1);
    if (turns > 10000.0 || turns < -10000.0) { reply("ERR 4 out of range"); return; }
    goal[m] = (long)(turns * STEPS_PER_TURN);
    enabled = true;
    digitalWrite(ENABLE_PIN, LOW);
    snprintf(buf, sizeof(buf), "OK G %d", id);
    reply(buf);
  }
}

void setup() {
  Serial.begin(115200);
  pinMode(ENABLE_PIN, OUTPUT);
  digitalWrite(ENABLE_PIN, HIGH);
  for (int i = 0; i < N_MOTORS; i++) {
    pinMode(STEP_PIN[i], OUTPUT);
    pinMode(DIR_PIN[i], OUTPUT);
    position[i] = goal[i] = 0;
  }
}

void loop() {
  while (Serial.available()) {
    char c = Serial.read();
    if (c == '\r') continue;
    if (c == '\n') { line[lineLen] = '\0'; if (lineLen) handle(line); lineLen = 0; }
    else if (lineLen < (int)sizeof(line) - 1) line[lineLen++] = c;
  }
  if (enabled && micros() - lastStep >= STEP_INTERVAL_US) {
    lastStep = micros();
    for (int i = 0; i < N_MOTORS; i++) {
      if (position[i] == goal[i]) continue;
      bool forward = goal[i] > position[i];
      digitalWrite(DIR_PIN[i], forward ? HIGH : LOW);
      digitalWrite(STEP_PIN[i], HIGH);
      delayMicroseconds(2);
      digitalWrite(STEP_PIN[i], LOW);
      position[i] += forward ? 1 : -1;
    }
  }
}
