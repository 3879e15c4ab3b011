/* An Eclipse Cyclone DDS subscriber (C API, types from scanbus_cyclone.idl by Cyclone's
 * idlc): takes COUNT samples of one scanbus topic within SECONDS and prints each as one
 * JSON line of its contents, for cyclone_interop.sh to compare with what scanbus sent.
 *   cyclone_subscriber cloud|scan|room TOPIC COUNT SECONDS
 * Domain: SCANBUS_DOMAIN_ID. Network: CYCLONEDDS_URI (the test keeps it on 127.0.0.1). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dds/dds.h"
#include "scanbus_cyclone.h"

static void print_cloud(const sensor_msgs_msg_dds__PointCloud2_* cloud) {
  unsigned long long sum = 0;
  for (uint32_t i = 0; i < cloud->data._length; ++i) sum += cloud->data._buffer[i];
  printf("{\"stamp\": %d.%09u, \"frame_id\": \"%s\", \"height\": %u, \"width\": %u, \"fields\": [", cloud->header.stamp.sec,
         cloud->header.stamp.nanosec, cloud->header.frame_id, cloud->height, cloud->width);
  for (uint32_t i = 0; i < cloud->fields._length; ++i)
    printf("%s\"%s\"", i ? ", " : "", cloud->fields._buffer[i].name);
  printf("], \"point_step\": %u, \"data_size\": %u, \"data_sum\": %llu}\n", cloud->point_step, cloud->data._length, sum);
}

static void print_scan(const sensor_msgs_msg_dds__LaserScan_* scan) {
  /* In whole millimetres: exact on both sides, whatever a float's decimal text looks like. */
  long long millimetres = 0;
  for (uint32_t i = 0; i < scan->ranges._length; ++i) millimetres += llround(scan->ranges._buffer[i] * 1000.0);
  printf("{\"stamp\": %d.%09u, \"frame_id\": \"%s\", \"angle_min\": %.6f, \"angle_increment\": %.8f, \"ranges\": %u, "
         "\"range_sum_mm\": %lld}\n", scan->header.stamp.sec, scan->header.stamp.nanosec, scan->header.frame_id,
         scan->angle_min, scan->angle_increment, scan->ranges._length, millimetres);
}

static void print_room(const scanbus_msg_dds__RoomMeasurement_* room) {
  printf("{\"frame_id\": \"%s\", \"walls\": [", room->header.frame_id);
  for (uint32_t i = 0; i < room->walls._length; ++i) printf("%s%.9f", i ? ", " : "", room->walls._buffer[i].length);
  printf("], \"corners\": %u, \"floor_area\": %.9f, \"perimeter\": %.9f, \"status\": %u, \"message\": \"%s\"}\n",
         room->corners._length, room->floor_area, room->perimeter, room->status, room->message);
}

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: cyclone_subscriber cloud|scan|room TOPIC COUNT SECONDS\n");
    return 2;
  }
  const char* kind = argv[1];
  const dds_topic_descriptor_t* descriptor = strcmp(kind, "cloud") == 0  ? &sensor_msgs_msg_dds__PointCloud2__desc
                                             : strcmp(kind, "scan") == 0 ? &sensor_msgs_msg_dds__LaserScan__desc
                                                                         : &scanbus_msg_dds__RoomMeasurement__desc;
  const int count = atoi(argv[3]);
  const dds_time_t deadline = dds_time() + (dds_duration_t)(atof(argv[4]) * 1e9);
  const char* domain_text = getenv("SCANBUS_DOMAIN_ID");
  const dds_domainid_t domain = domain_text ? (dds_domainid_t)atoi(domain_text) : 0;

  const dds_entity_t participant = dds_create_participant(domain, NULL, NULL);
  if (participant < 0) {
    fprintf(stderr, "cyclone_subscriber: dds_create_participant: %s\n", dds_strretcode(-participant));
    return 1;
  }
  const dds_entity_t topic = dds_create_topic(participant, descriptor, argv[2], NULL, NULL);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(10));
  dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  /* Latched topics: transient local, to get the sample written before we joined. */
  if (strcmp(kind, "scan") != 0) dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, NULL);
  dds_delete_qos(qos);
  if (topic < 0 || reader < 0) {
    fprintf(stderr, "cyclone_subscriber: cannot create the topic or reader on %s\n", argv[2]);
    return 1;
  }
  fprintf(stderr, "ready\n");

  int taken = 0;
  void* samples[1] = {NULL};
  dds_sample_info_t info;
  while (taken < count && dds_time() < deadline) {
    const dds_return_t n = dds_take(reader, samples, &info, 1, 1);
    if (n <= 0) {
      dds_sleepfor(DDS_MSECS(5));
      continue;
    }
    if (!info.valid_data) continue;
    if (strcmp(kind, "cloud") == 0) print_cloud(samples[0]);
    else if (strcmp(kind, "scan") == 0) print_scan(samples[0]);
    else print_room(samples[0]);
    fflush(stdout);
    ++taken;
    dds_return_loan(reader, samples, n);
    samples[0] = NULL;
  }
  dds_delete(participant);
  if (taken < count) {
    fprintf(stderr, "cyclone_subscriber: %d of %d samples on %s within %s s\n", taken, count, argv[2], argv[4]);
    return 1;
  }
  return 0;
}
