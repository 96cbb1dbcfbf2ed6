#!/bin/sh
# a file for check_links_selftest.sh to find
